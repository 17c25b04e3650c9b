// Triangulation (thesis 3.7): each method recovers synthetic points, reports residuals, and its
// covariance matches the scatter of a Monte Carlo run with the same pixel noise.
#include "common/geometry/triangulation.h"

#include <gtest/gtest.h>

#include "tests/common/geometry/synthetic_rig.h"

namespace igms::geometry {
namespace {

using testing::RandomScenePoint;
using testing::ThesisLikeRig;

constexpr TriangulationMethod kMethods[] = {
    TriangulationMethod::kLinear, TriangulationMethod::kMidpoint, TriangulationMethod::kRefined};

TEST(Triangulation, RecoversExactPointsWithZeroResidual) {
  const auto rig = ThesisLikeRig();
  std::mt19937 rng(10);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d X = RandomScenePoint(rng);
    for (auto method : kMethods) {
      auto t = Triangulate(rig.left.P(), rig.right.P(), *rig.left.Project(X), *rig.right.Project(X),
                           method, {});
      ASSERT_TRUE(t.ok()) << ToString(method) << ": " << t.error();
      EXPECT_LT((t->point - X).norm(), 1e-7) << ToString(method);
      EXPECT_LT(t->rms_error, 1e-7);
      EXPECT_NEAR(t->left_depth, rig.left.Depth(X), 1e-6);
      EXPECT_NEAR(t->right_depth, rig.right.Depth(X), 1e-6);
    }
  }
}

TEST(Triangulation, RefinedHasTheSmallestReprojectionError) {
  const auto rig = ThesisLikeRig();
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 1.0);
  double sum[3] = {0, 0, 0};
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d X = RandomScenePoint(rng);
    const Eigen::Vector2d l = *rig.left.Project(X) + Eigen::Vector2d(noise(rng), noise(rng));
    const Eigen::Vector2d r = *rig.right.Project(X) + Eigen::Vector2d(noise(rng), noise(rng));
    double rms[3];
    for (int m = 0; m < 3; ++m) {
      auto t = Triangulate(rig.left.P(), rig.right.P(), l, r, kMethods[m], {.pixel_sigma = 0});
      ASSERT_TRUE(t.ok());
      rms[m] = t->rms_error;
      sum[m] += rms[m];
      // Residuals are what the rms summarises.
      EXPECT_NEAR(rms[m],
                  std::sqrt((t->left_residual.squaredNorm() + t->right_residual.squaredNorm()) / 2),
                  1e-12);
    }
    EXPECT_LE(rms[2], rms[0] + 1e-9);
    EXPECT_LE(rms[2], rms[1] + 1e-9);
  }
  // The optimum splits the epipolar disagreement evenly over the two images; with unit noise
  // the rms is about sqrt(1/2) times the half-distance of the two pixels from their lines.
  EXPECT_LT(sum[2] / 300, sum[1] / 300);
  EXPECT_GT(sum[2] / 300, 0.1);
}

TEST(Triangulation, CovarianceMatchesMonteCarlo) {
  const auto rig = ThesisLikeRig();
  const Eigen::Vector3d X(72, 3, 4);
  const Eigen::Vector2d l0 = *rig.left.Project(X), r0 = *rig.right.Project(X);
  const double sigma = 0.5;
  std::mt19937 rng(12);
  std::normal_distribution<double> noise(0.0, sigma);
  for (auto method : kMethods) {
    auto clean = Triangulate(rig.left.P(), rig.right.P(), l0, r0, method, {.pixel_sigma = sigma});
    ASSERT_TRUE(clean.ok());
    const int n = 4000;
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (int i = 0; i < n; ++i) {
      auto t =
          Triangulate(rig.left.P(), rig.right.P(), l0 + Eigen::Vector2d(noise(rng), noise(rng)),
                      r0 + Eigen::Vector2d(noise(rng), noise(rng)), method, {.pixel_sigma = 0});
      ASSERT_TRUE(t.ok());
      const Eigen::Vector3d e = t->point - X;
      scatter += e * e.transpose();
    }
    scatter /= n;
    // Depth dominates (about 1 inch at 6 feet with a 4-inch baseline): compare the largest
    // eigenvalue and the whole matrix.
    const double predicted = clean->covariance.trace(), measured = scatter.trace();
    EXPECT_NEAR(measured / predicted, 1.0, 0.1) << ToString(method);
    EXPECT_LT((scatter - clean->covariance).norm() / clean->covariance.norm(), 0.15)
        << ToString(method);
    EXPECT_GT(predicted, 0.1) << "depth uncertainty at 6 ft must be visible";
  }
}

TEST(Triangulation, RefusesParallelRaysBehindCameraAndNaN) {
  const auto rig = ThesisLikeRig();
  for (auto method : kMethods) {
    // The same camera twice: every pair of rays through one centre is degenerate.
    const auto same = Triangulate(rig.left.P(), rig.left.P(), {100, 100}, {100, 100}, method, {});
    EXPECT_FALSE(same.ok()) << ToString(method);
    EXPECT_FALSE(same.error().empty());
    // Pixels whose rays cross behind the cameras (diverging: left pixel far left, right far right).
    const Eigen::Vector3d X(60, 0, 2);
    const Eigen::Vector2d l = *rig.left.Project(X), r = *rig.right.Project(X);
    const auto behind = Triangulate(rig.left.P(), rig.right.P(), l + Eigen::Vector2d(-60, 0),
                                    r + Eigen::Vector2d(60, 0), method, {});
    EXPECT_FALSE(behind.ok()) << ToString(method);
    EXPECT_NE(behind.error().find("behind"), std::string::npos) << behind.error();
    const auto not_finite = Triangulate(rig.left.P(), rig.right.P(), {NAN, 1}, r, method, {});
    EXPECT_FALSE(not_finite.ok());
    EXPECT_NE(not_finite.error().find("finite"), std::string::npos);
    EXPECT_FALSE(Triangulate(rig.left.P(), rig.right.P(), l, r, method, {.pixel_sigma = -1}).ok());
  }
}

TEST(Triangulation, OffEpipolarPairsReportTheirResidual) {
  const auto rig = ThesisLikeRig();
  const Eigen::Vector3d X(50, -2, 5);
  // Moving the right pixel 3 px vertically (the rig is horizontal) breaks the epipolar
  // constraint by about 3 px; the refined point splits it between the images.
  auto t =
      Triangulate(rig.left.P(), rig.right.P(), *rig.left.Project(X),
                  *rig.right.Project(X) + Eigen::Vector2d(0, 3), TriangulationMethod::kRefined);
  ASSERT_TRUE(t.ok());
  EXPECT_NEAR(t->left_residual.norm() + t->right_residual.norm(), 3.0, 0.1);
  EXPECT_NEAR(t->left_residual.norm(), t->right_residual.norm(), 0.1);
}

}  // namespace
}  // namespace igms::geometry
