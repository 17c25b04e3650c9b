// DLT calibration (thesis 3.2): both formulations recover synthetic cameras, report honest
// residuals under noise, and refuse degenerate input.
#include "common/calibration/dlt.h"

#include <gtest/gtest.h>

#include "common/geometry/decomposition.h"
#include "tests/common/geometry/synthetic_rig.h"

namespace igms::calibration {
namespace {

// The thesis-like rig with its world origin moved 30 inches out in front of the cameras, as
// the thesis's was (its C34 = 1 form needs the origin off the focal plane).
const Eigen::Vector3d kShift(30, 0, 0);

geometry::ProjectiveCamera TestCamera() {
  const auto cam = testing::ThesisLikeRig().left;
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topRightCorner<3, 1>() = kShift;
  return geometry::ProjectiveCamera(cam.P() * T, cam.image_size());
}

Eigen::Vector3d ScenePoint(std::mt19937& rng) { return testing::RandomScenePoint(rng) - kShift; }

std::vector<Correspondence> Synthetic(const geometry::ProjectiveCamera& cam, int n, double noise,
                                      int seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0, noise);
  std::vector<Correspondence> out;
  while (static_cast<int>(out.size()) < n) {
    const Eigen::Vector3d X = ScenePoint(rng);
    const auto px = cam.Project(X);
    if (!px || !cam.InImage(*px)) continue;
    out.push_back({X, *px + Eigen::Vector2d(gauss(rng), gauss(rng))});
  }
  return out;
}

// RMS pixel distance between two cameras' images of scene points inside the image.
double PixelError(const geometry::Matrix34& a, const geometry::Matrix34& b, int seed) {
  std::mt19937 rng(seed);
  const geometry::ProjectiveCamera A(a, {512, 480}), B(b, {512, 480});
  double sum = 0;
  int n = 0;
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d X = ScenePoint(rng);
    const auto pb = B.Project(X);
    if (!pb || !B.InImage(*pb)) continue;
    sum += (*A.Project(X) - *pb).squaredNorm();
    ++n;
  }
  return std::sqrt(sum / n);
}

TEST(Dlt, ExactDataGivesTheCamera) {
  const auto cam = TestCamera();
  const auto points = Synthetic(cam, 6, 0.0, 50);
  for (auto method : {DltMethod::kThesis, DltMethod::kNormalized}) {
    auto r = CalibrateDlt(points, method);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_LT(r->rms, 1e-6) << ToString(method);
    EXPECT_LT(PixelError(r->P, cam.P(), 51), 1e-5) << ToString(method);
  }
  EXPECT_DOUBLE_EQ(CalibrateDlt(points, DltMethod::kThesis)->P(2, 3), 1.0);
}

TEST(Dlt, HalfPixelNoiseOnTwentyPoints) {
  const auto cam = TestCamera();
  double rms[2] = {0, 0}, err[2] = {0, 0};
  const int trials = 50;
  for (int t = 0; t < trials; ++t) {
    const auto points = Synthetic(cam, 20, 0.5, 100 + t);
    for (int m = 0; m < 2; ++m) {
      auto r = CalibrateDlt(points, m == 0 ? DltMethod::kThesis : DltMethod::kNormalized);
      ASSERT_TRUE(r.ok()) << r.error();
      ASSERT_EQ(r->residuals.size(), 20u);
      rms[m] += r->rms / trials;
      err[m] += PixelError(r->P, cam.P(), t) / trials;
    }
  }
  // 40 equations, 11 unknowns: the residual (a 2D distance) has rms about
  // sigma * sqrt(2 (40 - 11) / 40) = 0.60 px; the fitted camera is within a pixel.
  for (int m = 0; m < 2; ++m) {
    EXPECT_GT(rms[m], 0.4);
    EXPECT_LT(rms[m], 0.7);
    EXPECT_LT(err[m], 1.0);
  }
}

TEST(Dlt, RefusesDegenerateInput) {
  const auto cam = TestCamera();
  auto points = Synthetic(cam, 12, 0.0, 60);
  std::string why;
  for (auto method : {DltMethod::kThesis, DltMethod::kNormalized}) {
    why = CalibrateDlt(std::span(points).first(5), method).error();
    EXPECT_NE(why, "");
    EXPECT_NE(why.find("at least 6"), std::string::npos);
    auto flat = points;
    for (auto& p : flat) {
      p.world.z() = 0;
      p.pixel = *cam.Project(p.world);
    }
    why = CalibrateDlt(flat, method).error();
    EXPECT_NE(why, "");
    EXPECT_NE(why.find("coplanar"), std::string::npos) << why;
    auto bad = points;
    bad[3].pixel.x() = NAN;
    why = CalibrateDlt(bad, method).error();
    EXPECT_NE(why, "");
    EXPECT_NE(why.find("correspondence 4"), std::string::npos);
  }
}

TEST(Dlt, ParsesCorrespondenceText) {
  std::string why;
  auto pts = ParseCorrespondences("# x y z u v\n1 2 3 4 5\n\n6,7,8,9,10  # note\n");
  ASSERT_TRUE(pts.ok()) << pts.error();
  ASSERT_EQ(pts->size(), 2u);
  EXPECT_EQ((*pts)[1].world, Eigen::Vector3d(6, 7, 8));
  EXPECT_EQ((*pts)[1].pixel, Eigen::Vector2d(9, 10));
  why = ParseCorrespondences("1 2 3 4\n").error();
  EXPECT_NE(why, "");
  EXPECT_NE(why.find("line 1: expected 5 numbers"), std::string::npos);
  why = ParseCorrespondences("1 2 3 4 5\n1 2 x 4 5\n").error();
  EXPECT_NE(why, "");
  EXPECT_NE(why.find("line 2"), std::string::npos);
  why = ParseCorrespondences("1 2 3 4 nan\n").error();
  EXPECT_NE(why, "");
}

}  // namespace
}  // namespace igms::calibration
