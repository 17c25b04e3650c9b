// `igms-locate` as a real process: JSON on stdout and exit status 0 found, 1 not found,
// 2 bad input, on a rendered scene written to files.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "common/calibration/calibration_file.h"
#include "common/sim/marks.h"
#include "common/sim/range.h"
#include "common/sim/renderer.h"
#include "common/sim/testbed.h"
#include "tests/support/child_process.h"

namespace fs = std::filesystem;

namespace igms::object {
namespace {

struct ProcessRun {
  int status = -1;
  std::string out;
};

// Runs igms-locate; its stderr is dropped, or read after stdout with `with_stderr`.
ProcessRun Exec(const std::string& args, bool with_stderr = false) {
  const char* bin = std::getenv("IGMS_BIN_DIR");
  const std::string cmd = std::string(bin ? bin : ".") + "/igms-locate " + args +
                          (with_stderr ? " 2>&1" : " 2>/dev/null");
  const igms::testing::ShellRun run = igms::testing::RunShell(cmd);
  return {run.status, run.out};
}

std::string MarkArgs(const site::Marks& marks) {
  std::ostringstream s;
  s.precision(10);
  for (const auto& m : marks) s << " --mark " << m.x() << "," << m.y() << "," << m.z();
  return s.str();
}

// Whether the JSON text is an object (its opening brace, 0x7b, first) whose first members are
// `members`.
bool JsonBegins(const std::string& json, const std::string& members) {
  return !json.empty() && json[0] == 0x7b && json.compare(1, members.size(), members) == 0;
}

double JsonNumber(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\": ");
  if (at == std::string::npos) return std::nan("");
  return std::atof(json.c_str() + at + key.size() + 4);
}

class LocateCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("igms_locate_cli_" + std::to_string(getpid()));
    fs::create_directories(dir_);
    scene_ = site::RandomTestbedScene(77);
    const auto images = site::RenderStereo(scene_);
    cv::imwrite((dir_ / "left.png").string(), images.left);
    cv::imwrite((dir_ / "right.png").string(), images.right);
    calibration::StereoCalibration cal;
    cal.left.P = scene_.cameras.left.P();
    cal.left.image_size = scene_.cameras.left.image_size();
    cal.right.P = scene_.cameras.right.P();
    cal.right.image_size = scene_.cameras.right.image_size();
    std::string error;
    ASSERT_TRUE(calibration::SaveCalibration(cal, (dir_ / "cal.yaml").string(), &error)) << error;
    base_ = "--calibration " + (dir_ / "cal.yaml").string() + " --left " +
            (dir_ / "left.png").string() + " --right " + (dir_ / "right.png").string();
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
  site::Scene scene_;
  std::string base_;
};

TEST_F(LocateCli, FindsEachObjectAndPrintsJson) {
  int checked = 0;
  for (size_t i = 0; i < scene_.objects.size(); ++i) {
    const auto& shape = scene_.objects[i].shape;
    const auto marks = *site::GenerateMarks(shape, scene_.cameras.left, 31 + i);
    if (const auto* c = std::get_if<site::Cylinder>(&shape)) {
      const ProcessRun r = Exec(base_ + " --type cylinder --json" + MarkArgs(marks));
      ASSERT_EQ(r.status, 0) << r.out;
      EXPECT_TRUE(JsonBegins(r.out, "\"found\": true, \"type\": \"cylinder\"")) << r.out;
      EXPECT_NEAR(JsonNumber(r.out, "radius"), c->radius, 0.05) << r.out;
      EXPECT_NEAR(JsonNumber(r.out, "height"), c->height, 0.3) << r.out;
      EXPECT_NE(r.out.find("\"axis\": ["), std::string::npos);
      ++checked;
    } else if (std::holds_alternative<site::Box>(shape)) {
      const ProcessRun r = Exec(base_ + " --type box --json" + MarkArgs(marks));
      ASSERT_EQ(r.status, 0) << r.out;
      EXPECT_NE(r.out.find("\"min\": ["), std::string::npos) << r.out;
      EXPECT_NE(r.out.find("\"max\": ["), std::string::npos) << r.out;
      ++checked;
    }
  }
  EXPECT_GE(checked, 3);
}

TEST_F(LocateCli, NotFoundExitsOne) {
  const Eigen::Vector3d c = scene_.cameras.left.Center();
  const double y = c.y() - 200;
  const std::string marks = " --mark " + std::to_string(c.x() - 3) + "," + std::to_string(y) +
                            ",33" + " --mark " + std::to_string(c.x() + 3) + "," +
                            std::to_string(y) + ",33" + " --mark " + std::to_string(c.x() + 3) +
                            "," + std::to_string(y) + ",27" + " --mark " +
                            std::to_string(c.x() - 3) + "," + std::to_string(y) + ",27";
  const ProcessRun r = Exec(base_ + " --type box --json" + marks);
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_TRUE(JsonBegins(r.out, "\"found\": false")) << r.out;
  EXPECT_NE(r.out.find("\"reason\": \"no_edge_near_marks\""), std::string::npos) << r.out;
}

TEST_F(LocateCli, BadInputExitsTwo) {
  const std::string four = " --mark 1,-50,1 --mark 2,-50,1 --mark 2,-50,2 --mark 1,-50,2";
  EXPECT_EQ(Exec(base_ + " --type cylinder --mark 1,2,3").status, 2);  // one mark
  EXPECT_EQ(Exec(base_ + " --type cone" + four).status, 2);            // unknown type
  EXPECT_EQ(Exec(base_ + " --type box --mark 1,2 --mark 1,2,3 --mark 1,2,3 --mark 1,2,3").status,
            2);
  EXPECT_EQ(
      Exec(base_ + " --type box --mark nan,2,3 --mark 1,2,3 --mark 1,2,3 --mark 1,2,3").status, 2);
  EXPECT_EQ(
      Exec("--calibration /nonexistent.yaml --left a.png --right b.png --type box" + four).status,
      2);
  std::FILE* f = std::fopen((dir_ / "junk.yaml").c_str(), "w");
  std::fputs("this: [is not, a calibration", f);
  std::fclose(f);
  EXPECT_EQ(Exec("--calibration " + (dir_ / "junk.yaml").string() +
                 " --left a.png --right b.png --type box" + four)
                .status,
            2);
  EXPECT_EQ(Exec("--calibration " + (dir_ / "cal.yaml").string() +
                 " --left /nonexistent.png --right b.png --type box" + four)
                .status,
            2);
  EXPECT_EQ(Exec("--bogus-flag").status, 2);
  const ProcessRun blur = Exec(base_ + " --type box" + four + " --camera-blur -1", true);
  EXPECT_EQ(blur.status, 2);
  EXPECT_NE(blur.out.find("camera_blur_px must be in 0..10"), std::string::npos) << blur.out;
  const ProcessRun floor = Exec(base_ + " --type box" + four + " --floor-height nan", true);
  EXPECT_EQ(floor.status, 2);
  EXPECT_NE(floor.out.find("floor_height must be a finite number"), std::string::npos) << floor.out;
}

TEST_F(LocateCli, DebugImageShowsEdgesPointsAndOutline) {
  for (size_t i = 0; i < scene_.objects.size(); ++i) {
    const auto& shape = scene_.objects[i].shape;
    if (!std::holds_alternative<site::Cylinder>(shape)) continue;
    const auto marks = *site::GenerateMarks(shape, scene_.cameras.left, 31 + i);
    const std::string file = (dir_ / "debug.png").string();
    const ProcessRun r = Exec(base_ + " --type cylinder --debug-image " + file + MarkArgs(marks));
    ASSERT_EQ(r.status, 0) << r.out;
    const cv::Mat img = cv::imread(file, cv::IMREAD_COLOR);
    ASSERT_FALSE(img.empty());
    EXPECT_EQ(img.cols, 2 * 512);
    EXPECT_GE(img.rows, 2 * 480);
    int magenta = 0, green = 0, blue = 0;
    for (int y = 0; y < img.rows; ++y)
      for (int x = 0; x < img.cols; ++x) {
        const cv::Vec3b& p = img.at<cv::Vec3b>(y, x);
        magenta += p[0] > 200 && p[1] < 80 && p[2] > 200;
        green += p[0] < 60 && p[1] > 180 && p[2] < 60;
        blue += p[0] > 200 && p[1] > 100 && p[1] < 180 && p[2] < 60;
      }
    EXPECT_GT(magenta, 200) << "the fitted outline";
    EXPECT_GT(green, 100) << "the measured edge points";
    EXPECT_GT(blue, 50) << "the strong edges";
    // An unwritable file is reported, and the result still printed.
    const ProcessRun bad =
        Exec(base_ + " --type cylinder --debug-image /nonexistent/dir/x.png" + MarkArgs(marks));
    EXPECT_EQ(bad.status, 0);
    return;
  }
  FAIL() << "the scene has no cylinder";
}

// The ranger in a calibration of our own (a nominal one for the lab is not relied on): 6 in
// above the left camera, aimed at an upright cylinder. The range the simulated ranger would
// measure off that cylinder alone agrees; one 8 in longer is reported as a disagreement.
TEST_F(LocateCli, RangeConstrainsAndIsChecked) {
  const site::Cylinder* cyl = nullptr;
  size_t index = 0;
  for (size_t i = 0; i < scene_.objects.size() && !cyl; ++i)
    if (const auto* c = std::get_if<site::Cylinder>(&scene_.objects[i].shape);
        c && c->axis.z() > 0.9) {
      cyl = c;
      index = i;
    }
  ASSERT_NE(cyl, nullptr);
  calibration::StereoCalibration cal = *calibration::LoadCalibration((dir_ / "cal.yaml").string());
  const Eigen::Vector3d origin = scene_.cameras.left.Center() + Eigen::Vector3d(0, 0, 6);
  const Eigen::Vector3d axis = (cyl->center - origin).normalized();
  cal.ranger = calibration::RangerCalibration{origin, axis};
  ASSERT_TRUE(calibration::SaveCalibration(cal, (dir_ / "ranger.yaml").string()));
  site::Scene alone = scene_;
  alone.objects = {scene_.objects[index]};
  alone.table.enabled = false;
  const auto range = site::RangeInCone(alone, origin, axis, 6.0 * M_PI / 180);
  ASSERT_TRUE(range.has_value());

  const std::string args = "--calibration " + (dir_ / "ranger.yaml").string() + " --left " +
                           (dir_ / "left.png").string() + " --right " +
                           (dir_ / "right.png").string() + " --type cylinder --json" +
                           MarkArgs(*site::GenerateMarks(*cyl, scene_.cameras.left, 5));
  const ProcessRun good = Exec(args + " --range " + std::to_string(*range));
  ASSERT_EQ(good.status, 0) << good.out;
  EXPECT_NE(good.out.find("\"constrained\": true"), std::string::npos) << good.out;
  EXPECT_NE(good.out.find("\"agrees\": true"), std::string::npos) << good.out;
  EXPECT_NEAR(JsonNumber(good.out, "height"), cyl->height, 0.3) << good.out;

  const ProcessRun far = Exec(args + " --range " + std::to_string(*range + 8));
  ASSERT_EQ(far.status, 0) << far.out;  // the marks' depth still finds it
  EXPECT_NE(far.out.find("\"constrained\": false"), std::string::npos) << far.out;
  EXPECT_NE(far.out.find("\"agrees\": false"), std::string::npos) << far.out;
  EXPECT_NE(far.out.find("beyond where the beam meets"), std::string::npos) << far.out;

  const ProcessRun near = Exec(args + " --range " + std::to_string(*range - 2));
  EXPECT_NE(near.out.find("something nearer is in the beam"), std::string::npos) << near.out;

  // A range without a ranger in the calibration, or a nonsensical one, is bad input.
  EXPECT_EQ(Exec(base_ + " --type cylinder --range 50" +
                 MarkArgs(*site::GenerateMarks(*cyl, scene_.cameras.left, 5)))
                .status,
            2);
  EXPECT_EQ(Exec(args + " --range -3").status, 2);
}

}  // namespace
}  // namespace igms::object
