// The calibration file: the thesis's matrices load, round trips are exact, and every kind of
// bad input is refused with the offending key named.
#include "common/calibration/calibration_file.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "tests/common/geometry/synthetic_rig.h"

namespace igms::calibration {
namespace {

std::string SourceDir() {
  const char* dir = std::getenv("IGMS_SOURCE_DIR");
  return dir ? dir : ".";
}

const char* kMinimal = R"(%YAML:1.0
---
left:
   P: !!opencv-matrix
      rows: 3
      cols: 4
      dt: d
      data: [ -232.71, -64.35, 4.45, 5031.32, -5.22, -63.50, -285.65, 1379.56, -0.01, -0.24, 0.01, 1.00 ]
   image_size: [ 512, 480 ]
right:
   P: !!opencv-matrix
      rows: 3
      cols: 4
      dt: d
      data: [ -214.44, -60.906, 4.84, 3844.42, -4.93, -58.97, -261.44, 1294.73, -0.01, -0.22, 0.01, 1.00 ]
   image_size: [ 512, 480 ]
)";

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

std::string ErrorOf(const std::string& yaml) {
  const auto parsed = ParseCalibration(yaml);
  EXPECT_FALSE(parsed.ok()) << yaml;
  return parsed.error();
}

TEST(CalibrationFile, ThesisFileLoads) {
  auto c = LoadCalibration(SourceDir() + "/common/calibration/data/thesis_calibration.yaml");
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_DOUBLE_EQ(c->left.P(0, 0), -232.71);
  EXPECT_DOUBLE_EQ(c->right.P(0, 1), -60.906);
  EXPECT_DOUBLE_EQ(c->right.P(2, 3), 1.0);
  EXPECT_EQ(c->left.image_size.width, 512);
  EXPECT_EQ(c->right.image_size.height, 480);
  EXPECT_FALSE(c->left.K);
  // The nominal platform: pan axis vertical through the midpoint of the camera centres, the
  // thesis's tick scales, and the ranger between the cameras along their mean optical axis.
  ASSERT_TRUE(c->platform);
  ASSERT_EQ(c->platform->joints.size(), 3u);
  EXPECT_NEAR(c->platform->joints[0].radians_per_tick,
              geometry::ThesisPanDegreesPerTick() * M_PI / 180, 1e-15);
  EXPECT_NEAR(c->platform->joints[1].radians_per_tick,
              geometry::ThesisTiltDegreesPerTick() * M_PI / 180, 1e-15);
  const Eigen::Vector3d middle = (c->left.Camera().Center() + c->right.Camera().Center()) / 2;
  const Eigen::Vector3d pan_point = c->platform->world_from_base.translation();
  EXPECT_NEAR((pan_point - middle).head<2>().norm(), 0.0, 0.01);
  EXPECT_TRUE(c->platform->world_from_base.linear().col(2).isApprox(Eigen::Vector3d::UnitZ()));
  const std::vector<double> zero(3, 0.0);
  const Eigen::Isometry3d world_from_end = geometry::WorldFromEnd(*c->platform, zero);
  ASSERT_TRUE(c->ranger);
  EXPECT_NEAR((world_from_end * c->ranger->origin - middle).norm(), 0.0, 0.01);
  const Eigen::Vector3d view =
      (c->left.Camera().ViewDirection() + c->right.Camera().ViewDirection()).normalized();
  EXPECT_GT((world_from_end.linear() * c->ranger->axis).dot(view), std::cos(1e-4));
  // The same text inline parses identically.
  auto inline_c = ParseCalibration(kMinimal);
  ASSERT_TRUE(inline_c.ok()) << inline_c.error();
  EXPECT_EQ(inline_c->left.P, c->left.P);
  // Centres sit near the thesis's printed values (section 4.2: about 21, 3, 4 inches).
  const Eigen::Vector3d centre = c->left.Camera().Center();
  EXPECT_TRUE(centre.allFinite());
}

TEST(CalibrationFile, RoundTripWithLensPlatformAndRanger) {
  const auto rig = testing::ThesisLikeRig();
  StereoCalibration c;
  c.left.P = rig.left.P();
  c.left.image_size = {640, 480};
  c.left.K = testing::Intrinsics(530.25, 320.1, 241.7);
  c.left.dist = {-0.28, 0.09, 1e-3, -2e-4, 0.01};
  c.right.P = rig.right.P() * 0.001;
  c.right.image_size = {640, 480};
  c.platform = geometry::ThesisPlatform({-2, 0, 1}, 5.5, 0.1);
  c.ranger = RangerCalibration{{1, 2, 3}, Eigen::Vector3d(1, 0, 0)};
  const auto dir =
      std::filesystem::temp_directory_path() / ("igms_calib_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "cal.yaml").string();
  std::string why;
  ASSERT_TRUE(SaveCalibration(c, path, &why)) << why;
  auto back = LoadCalibration(path);
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->left.P, c.left.P);  // cv::FileStorage writes doubles exactly
  EXPECT_EQ(back->right.P, c.right.P);
  ASSERT_TRUE(back->left.K);
  EXPECT_EQ(*back->left.K, *c.left.K);
  EXPECT_EQ(back->left.dist, c.left.dist);
  EXPECT_FALSE(back->right.K);
  ASSERT_TRUE(back->platform);
  ASSERT_EQ(back->platform->joints.size(), 3u);
  EXPECT_EQ(back->platform->joints[1].name, "tilt");
  EXPECT_DOUBLE_EQ(back->platform->joints[0].radians_per_tick,
                   c.platform->joints[0].radians_per_tick);
  EXPECT_TRUE(back->platform->world_from_base.isApprox(c.platform->world_from_base, 1e-15));
  ASSERT_TRUE(back->ranger);
  EXPECT_EQ(back->ranger->origin, Eigen::Vector3d(1, 2, 3));
  EXPECT_TRUE(back->left.Camera().has_distortion());
  std::filesystem::remove_all(dir);
}

TEST(CalibrationFile, DistAsPlainListAndColumnVector) {
  std::string yaml = std::string(kMinimal) + "ranger:\n   origin: [0, 0, 1]\n   axis: [0, 0, 2]\n";
  yaml =
      Replace(yaml, "   image_size: [ 512, 480 ]\nright:",
              "   image_size: [ 512, 480 ]\n   K: !!opencv-matrix\n      rows: 3\n      cols: 3\n"
              "      dt: d\n      data: [ 500, 0, 256, 0, 500, 240, 0, 0, 1 ]\n"
              "   dist: [ -0.1, 0.01, 0, 0 ]\nright:");
  auto c = ParseCalibration(yaml);
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_EQ(c->left.dist.size(), 4u);
  EXPECT_DOUBLE_EQ(c->ranger->axis.z(), 1.0);  // normalised
}

TEST(CalibrationFile, ErrorsNameTheKey) {
  EXPECT_NE(ErrorOf("%YAML:1.0\n---\nright: {}\n").find("left: missing"), std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kMinimal,
                            "      rows: 3\n      cols: 4\n      dt: d\n      data: [ -232.71, "
                            "-64.35, 4.45, 5031.32,",
                            "      rows: 3\n      cols: 3\n      dt: d\n      data: [ 1, 0, 0, 0, "
                            "1, 0, 0, 0, 1 ] #"))
                .find("left.P: expected a 3x4 matrix, got 3x3"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kMinimal, "-214.44", ".nan")).find("right.P"), std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kMinimal, "   image_size: [ 512, 480 ]\nright:", "right:"))
                .find("left.image_size: missing"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kMinimal, "   image_size: [ 512, 480 ]\nright:",
                            "   image_size: [ 512 ]\nright:"))
                .find("left.image_size"),
            std::string::npos);
  EXPECT_NE(ErrorOf(Replace(kMinimal, "   image_size: [ 512, 480 ]\nright:",
                            "   image_size: [ 0, 480 ]\nright:"))
                .find("left.image_size: width and height must be positive"),
            std::string::npos);
  // A singular left block: the camera centre is at infinity.
  EXPECT_NE(ErrorOf(Replace(kMinimal, "-214.44, -60.906, 4.84, 3844.42, -4.93, -58.97, -261.44",
                            "-0.01, -0.22, 0.01, 3844.42, -4.93, -58.97, -261.44"))
                .find("right.P: camera centre is not finite"),
            std::string::npos);
  EXPECT_NE(ErrorOf(std::string(kMinimal) + "   dist: [ 0.1, 0, 0, 0 ]\n")
                .find("right.dist: needs right.K"),
            std::string::npos);
  EXPECT_NE(ErrorOf(std::string(kMinimal) + "ranger:\n   origin: [0, 0]\n   axis: [1, 0, 0]\n")
                .find("ranger.origin"),
            std::string::npos);
  EXPECT_NE(ErrorOf(std::string(kMinimal) + "platform:\n   joints: []\n")
                .find("platform.world_from_base: missing"),
            std::string::npos);
  EXPECT_FALSE(ErrorOf("left: [unclosed").empty());
  EXPECT_FALSE(ErrorOf("").empty());
  EXPECT_FALSE(ErrorOf("%YAML:1.0\n---\nleft:\n   P: 5\n").empty());
  const auto missing = LoadCalibration("/nonexistent/cal.yaml");
  EXPECT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace igms::calibration
