// The pointer's geometry: the left camera's frame, the ultrasonic beam at a pose, and which
// model a point is inside.
#include "control/session/pointer.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/geometry/platform.h"
#include "tests/control/session/thesis_calibration.h"

namespace igms::control {
namespace {

TEST(CameraFrame, AxesOfTheThesisLeftCamera) {
  const auto cal = testing::ThesisCalibration();
  const geometry::ProjectiveCamera camera = cal.left.Camera();
  const auto f = CameraFrameOf(camera);
  ASSERT_TRUE(f);
  EXPECT_NEAR(f->right.norm(), 1.0, 1e-12);
  EXPECT_NEAR(f->right.dot(f->forward), 0.0, 1e-12);
  EXPECT_NEAR(f->down.dot(f->forward), 0.0, 1e-12);
  EXPECT_NEAR(f->right.dot(f->down), 0.0, 1e-12);
  EXPECT_LT((f->center - camera.Center()).norm(), 1e-12);
  // From a point on the optical axis at 36 in, a step right moves the image right, a step up
  // moves it up (v decreases), a step forward keeps it and deepens it.
  const Eigen::Vector3d p = f->OnAxis(36.0);
  const Eigen::Vector2d at = *camera.Project(p);
  const Eigen::Vector2d right = *camera.Project(p + 0.1 * f->right);
  const Eigen::Vector2d up = *camera.Project(p + 0.1 * f->up());
  EXPECT_GT(right.x() - at.x(), 2.0);
  EXPECT_NEAR(right.y(), at.y(), 0.05);
  EXPECT_LT(up.y() - at.y(), -2.0);
  EXPECT_NEAR(up.x(), at.x(), 0.05);
  EXPECT_NEAR(camera.Depth(p + f->forward), 37.0, 1e-9);
  // The thesis's cameras stand upright: the world's up is the image's up.
  EXPECT_GT(f->up().z(), 0.99);
}

TEST(Beam, TheCalibrationsRangerMovedByThePlatform) {
  const auto cal = testing::ThesisCalibration();
  const std::vector<double> q = {0.3, -0.1, 0.05};
  const Beam beam = BeamAt(cal, q);
  const Eigen::Isometry3d world_from_end = geometry::WorldFromEnd(*cal.platform, q);
  EXPECT_LT((beam.origin - world_from_end * cal.ranger->origin).norm(), 1e-12);
  EXPECT_LT((beam.axis - world_from_end.linear() * cal.ranger->axis.normalized()).norm(), 1e-12);
  // Missing joints are zero.
  const Beam panned = BeamAt(cal, std::vector<double>{0.3});
  EXPECT_LT((panned.origin - BeamAt(cal, std::vector<double>{0.3, 0, 0}).origin).norm(), 1e-12);
}

TEST(Beam, WithoutARangerMapBetweenTheCameras) {
  auto cal = testing::ThesisCalibration();
  cal.ranger.reset();
  const auto l = cal.left.Camera(), r = cal.right.Camera();
  const Beam zero = BeamAt(cal, std::vector<double>{0, 0, 0});
  EXPECT_LT((zero.origin - 0.5 * (l.Center() + r.Center())).norm(), 1e-9);
  EXPECT_LT((zero.axis - (l.ViewDirection() + r.ViewDirection()).normalized()).norm(), 1e-9);
  // At a pose it moves as the cameras do.
  const std::vector<double> q = {0.2, 0.1, 0};
  const Eigen::Isometry3d motion = geometry::WorldMotion(*cal.platform, q);
  const Beam moved = BeamAt(cal, q);
  EXPECT_LT((moved.origin - motion * zero.origin).norm(), 1e-9);
  EXPECT_LT((moved.axis - motion.linear() * zero.axis).norm(), 1e-9);
  // Without a platform model it never moves.
  cal.platform.reset();
  EXPECT_LT((BeamAt(cal, q).origin - zero.origin).norm(), 1e-9);
}

TEST(Contains, Cylinder) {
  object::CylinderModel c;
  *c.mutable_center() = ToVec3({10, 0, 0});
  *c.mutable_axis() = ToVec3({0, 0, 2});  // not unit: normalised
  c.set_radius(1.0);
  c.set_height(4.0);
  EXPECT_TRUE(CylinderContains(c, {10.5, 0.5, 1.9}));
  EXPECT_FALSE(CylinderContains(c, {10.5, 0.5, 2.1}));
  EXPECT_FALSE(CylinderContains(c, {11.1, 0, 0}));
  *c.mutable_axis() = ToVec3({0, 0, 0});
  EXPECT_FALSE(CylinderContains(c, {10, 0, 0}));
}

TEST(Contains, OrientedBoxAndWorldAlignedBlock) {
  object::BoxModel b;
  *b.mutable_center() = ToVec3({0, 0, 1});
  *b.mutable_size() = ToVec3({4, 1, 2});
  b.set_yaw_deg(45);
  // Along its own x axis (cos 45, sin 45, 0), 1.9 from the centre: inside; across it, not.
  const double s = std::sqrt(0.5);
  EXPECT_TRUE(BoxContains(b, {1.9 * s, 1.9 * s, 1}));
  EXPECT_FALSE(BoxContains(b, {-1.9 * s, 1.9 * s, 1}));
  EXPECT_FALSE(BoxContains(b, {0, 0, 2.1}));
  // Without an oriented size: the thesis's block, min and max.
  object::BoxModel block;
  *block.mutable_min() = ToVec3({0, 0, 0});
  *block.mutable_max() = ToVec3({1, 2, 3});
  EXPECT_TRUE(BoxContains(block, {0.5, 1.5, 2.5}));
  EXPECT_FALSE(BoxContains(block, {0.5, 2.5, 2.5}));
}

}  // namespace
}  // namespace igms::control
