// The ranger's beam at a platform pose against a pose worked out by hand.
#include "common/geometry/ranger_beam.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace igms::geometry {
namespace {

// Pan about the world's vertical through (10, 0, 0), then tilt about a horizontal axis 2
// above the base: A1(q1) = Rz(q1) Tz(2) Rx(90 deg), A2(q2) = Rz(q2).
PlatformModel PanTilt() {
  PlatformModel model;
  model.world_from_base = Eigen::Isometry3d(Eigen::Translation3d(10, 0, 0));
  DhJoint pan;
  pan.name = "pan";
  pan.d = 2;
  pan.alpha = M_PI / 2;
  DhJoint tilt;
  tilt.name = "tilt";
  model.joints = {pan, tilt};
  return model;
}

void ExpectNear(const Eigen::Vector3d& got, const Eigen::Vector3d& want) {
  EXPECT_LT((got - want).norm(), 1e-12) << got.transpose() << " vs " << want.transpose();
}

TEST(RangerBeam, MovesWithThePlatformAsWorkedOutByHand) {
  const std::optional<PlatformModel> platform = PanTilt();
  const Eigen::Vector3d origin_end(1, 0, 0), axis_end(0, 0, 3);  // axis of any length
  // Pan 90 and tilt 90 degrees. The origin: Rz(90) takes (1,0,0) to (0,1,0); Rx(90) takes
  // that to (0,0,1); Tz(2) to (0,0,3); Rz(90) leaves it; the base adds (10,0,0).
  // The axis: Rz(90) leaves z; Rx(90) takes it to (0,-1,0); Rz(90) to (1,0,0).
  const std::vector<double> q = {M_PI / 2, M_PI / 2};
  RangerBeam beam = RangerBeamAt(origin_end, axis_end, platform, q);
  ExpectNear(beam.origin, {10, 0, 3});
  ExpectNear(beam.axis, {1, 0, 0});
  // The zero pose, by an empty q: Rx(90) takes (1,0,0) to itself and z to -y.
  beam = RangerBeamAt(origin_end, axis_end, platform, {});
  ExpectNear(beam.origin, {11, 0, 2});
  ExpectNear(beam.axis, {0, -1, 0});
  // A missing tilt counts as zero: pan 90 alone turns the zero-pose beam about z.
  const std::vector<double> pan_only = {M_PI / 2};
  beam = RangerBeamAt(origin_end, axis_end, platform, pan_only);
  ExpectNear(beam.origin, {10, 1, 2});
  ExpectNear(beam.axis, {1, 0, 0});
  // Extra angles are ignored.
  const std::vector<double> extra = {M_PI / 2, M_PI / 2, 1.0};
  ExpectNear(RangerBeamAt(origin_end, axis_end, platform, extra).origin, {10, 0, 3});
}

TEST(RangerBeam, WithoutAPlatformTheEndFrameIsTheWorld) {
  const std::vector<double> q = {1.0, 2.0};
  const RangerBeam beam = RangerBeamAt({1, 2, 3}, {0, 4, 0}, std::nullopt, q);
  ExpectNear(beam.origin, {1, 2, 3});
  ExpectNear(beam.axis, {0, 1, 0});
}

}  // namespace
}  // namespace igms::geometry
