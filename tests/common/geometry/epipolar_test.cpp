// Epipolar geometry: lines contain the matches, the depth-window segment brackets them.
#include "common/geometry/epipolar.h"

#include <gtest/gtest.h>

#include "common/geometry/inverse_perspective.h"
#include "tests/common/geometry/synthetic_rig.h"

namespace igms::geometry {
namespace {

using testing::RandomScenePoint;
using testing::ThesisLikeRig;

TEST(Epipolar, MatchesLieOnTheirLinesBothWays) {
  const auto rig = ThesisLikeRig();
  const Eigen::Matrix3d F = FundamentalMatrix(rig.left.P(), rig.right.P());
  const Eigen::Matrix3d Fback = FundamentalMatrix(rig.right.P(), rig.left.P());
  EXPECT_NEAR(F.norm(), 1.0, 1e-12);
  // The reverse matrix is the transpose, up to sign.
  EXPECT_LT(std::min((F - Fback.transpose()).norm(), (F + Fback.transpose()).norm()), 1e-9);
  std::mt19937 rng(20);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d X = RandomScenePoint(rng);
    const Eigen::Vector2d l = *rig.left.Project(X), r = *rig.right.Project(X);
    const auto line = EpipolarLine(F, l);
    ASSERT_TRUE(line);
    EXPECT_NEAR(line->head<2>().norm(), 1.0, 1e-12);
    EXPECT_NEAR(LineDistance(*line, r), 0.0, 1e-7);
    EXPECT_NEAR(LineDistance(*EpipolarLine(Fback, r), l), 0.0, 1e-7);
    // A pixel 2 px off the line measures 2 px.
    const Eigen::Vector2d off = r + 2.0 * line->head<2>();
    EXPECT_NEAR(LineDistance(*line, off), 2.0, 1e-7);
  }
}

TEST(Epipolar, EpipoleIsTheOtherCentreAndHasNoLine) {
  const auto rig = ThesisLikeRig();
  const auto e = Epipole(rig.right.P(), rig.left.P());
  ASSERT_TRUE(e);
  EXPECT_LT((*e - *rig.left.Project(rig.right.Center())).norm(), 1e-9);
  // F maps right pixels to left lines; its null vector is the epipole in the right image and
  // its left null vector the epipole in the left image.
  const Eigen::Matrix3d F = FundamentalMatrix(rig.right.P(), rig.left.P());
  const auto e_in_right = Epipole(rig.left.P(), rig.right.P());
  ASSERT_TRUE(e_in_right);
  EXPECT_LT((F * e_in_right->homogeneous()).norm(), 1e-9);
  EXPECT_LT((F.transpose() * e->homogeneous()).norm(), 1e-9);
  EXPECT_FALSE(
      EpipolarLine(FundamentalMatrix(rig.left.P(), rig.right.P()).transpose(), *e_in_right));
  // Identical centres have no epipolar geometry.
  EXPECT_EQ(FundamentalMatrix(rig.left.P(), 2.0 * rig.left.P()).norm(), 0.0);
}

TEST(Epipolar, DepthWindowSegmentBracketsTheMatch) {
  const auto rig = ThesisLikeRig();
  const Eigen::Matrix3d F = FundamentalMatrix(rig.left.P(), rig.right.P());
  std::mt19937 rng(21);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d X = RandomScenePoint(rng);
    const Eigen::Vector2d l = *rig.left.Project(X), r = *rig.right.Project(X);
    const double depth = rig.left.Depth(X);
    const auto seg = ComputeEpipolarSegment(rig.left, rig.right, l, depth - 3, depth + 3);
    ASSERT_TRUE(seg.ok()) << seg.error();
    EXPECT_NEAR(rig.left.Depth(seg->near_world), depth - 3, 1e-9);
    EXPECT_NEAR(rig.left.Depth(seg->far_world), depth + 3, 1e-9);
    const auto line = *EpipolarLine(F, l);
    EXPECT_NEAR(LineDistance(line, seg->near), 0, 1e-7);
    EXPECT_NEAR(LineDistance(line, seg->far), 0, 1e-7);
    // The match lies between the ends.
    const Eigen::Vector2d a = seg->near, b = seg->far;
    const double s = (r - a).dot(b - a) / (b - a).squaredNorm();
    EXPECT_GT(s, 0.0);
    EXPECT_LT(s, 1.0);
    // A window that misses the point does not contain it.
    const auto beyond = ComputeEpipolarSegment(rig.left, rig.right, l, depth + 1, depth + 7);
    ASSERT_TRUE(beyond.ok());
    EXPECT_LT((r - beyond->near).dot(beyond->far - beyond->near), 0.0);
  }
}

TEST(Epipolar, SegmentRefusesBadWindows) {
  const auto rig = ThesisLikeRig();
  EXPECT_FALSE(ComputeEpipolarSegment(rig.left, rig.right, {256, 240}, 5, 4).ok());
  EXPECT_FALSE(ComputeEpipolarSegment(rig.left, rig.right, {256, 240}, 0, 4).ok());
  EXPECT_FALSE(ComputeEpipolarSegment(rig.left, rig.right, {256, 240}, NAN, 4).ok());
  // Two cameras facing each other: points near the first are behind the second.
  const Eigen::Matrix3d K = testing::Intrinsics(800, 256, 240);
  const ProjectiveCamera a(testing::LookAt(K, {0, 0, 0}, {10, 0, 0}), {512, 480});
  const ProjectiveCamera b(testing::LookAt(K, {10, 0.5, 0}, {0, 0, 0}), {512, 480});
  const auto behind = ComputeEpipolarSegment(a, b, {256, 240}, 5, 15);
  EXPECT_FALSE(behind.ok());
  EXPECT_NE(behind.error().find("behind"), std::string::npos);
  const auto in_front = ComputeEpipolarSegment(a, b, {256, 240}, 2, 8);
  EXPECT_TRUE(in_front.ok()) << in_front.error();
}

}  // namespace
}  // namespace igms::geometry
