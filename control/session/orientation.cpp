#include "control/session/orientation.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "common/geometry/platform.h"

namespace igms::control {
namespace {

constexpr double kDeg = M_PI / 180.0;
// SetOrientationRequest's range on the wire (docs/protocol-devices.md).
constexpr int32_t kYawLimit = 1048575;
constexpr int32_t kPitchRollLimit = 8191;

int32_t RoundTicks(double angle_rad, double radians_per_tick, int32_t limit) {
  const double t = std::round(angle_rad / radians_per_tick);
  if (!std::isfinite(t)) return 0;
  return static_cast<int32_t>(std::clamp(t, -static_cast<double>(limit), double(limit)));
}

}  // namespace

Eigen::Matrix3d RotationOf(const ViewerOrientation& o) {
  return (Eigen::AngleAxisd(o.yaw_deg * kDeg, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(o.pitch_deg * kDeg, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(o.roll_deg * kDeg, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

ViewerOrientation OrientationOf(const Eigen::Matrix3d& R) {
  ViewerOrientation o;
  o.pitch_deg = std::asin(std::clamp(-R(2, 0), -1.0, 1.0)) / kDeg;
  o.yaw_deg = std::atan2(R(1, 0), R(0, 0)) / kDeg;
  o.roll_deg = std::atan2(R(2, 1), R(2, 2)) / kDeg;
  return o;
}

Result<ViewerToPlatform> ViewerToPlatform::Make(const calibration::StereoCalibration& calibration,
                                                bool all_axes) {
  ViewerToPlatform m;
  m.all_axes_ = all_axes;
  if (!calibration.platform) {
    m.radians_per_tick_ = {geometry::ThesisPanDegreesPerTick() * kDeg,
                           geometry::ThesisTiltDegreesPerTick() * kDeg,
                           geometry::ThesisTiltDegreesPerTick() * kDeg};
    return m;
  }
  const geometry::PlatformModel& model = *calibration.platform;
  std::string why;
  if (!model.Check(&why)) {
    return ErrorMessage{"calibration platform: " + why};
  }
  m.joints_ = model.joints.size();
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d forward = calibration.left.Camera().ViewDirection();
  const Eigen::Vector3d left_dir = up.cross(forward);
  if (left_dir.norm() < 1e-6) {
    return ErrorMessage{"the left camera looks straight up or down at the platform's zero pose"};
  }
  const std::array<Eigen::Vector3d, 3> camera_axes = {up, left_dir.normalized(),
                                                      forward.normalized()};
  const char* axis_names[3] = {"the vertical", "the cameras' left", "the optical axis"};
  Eigen::Isometry3d frame = model.world_from_base;
  for (size_t i = 0; i < 3; ++i) {
    if (i >= model.joints.size()) {
      m.radians_per_tick_[i] = geometry::ThesisTiltDegreesPerTick() * kDeg;
      continue;
    }
    const geometry::DhJoint& joint = model.joints[i];
    const Eigen::Vector3d axis = frame.linear().col(2);
    const double along = axis.dot(camera_axes[i]);
    // A joint more than 60 degrees off the axis it stands for cannot follow the viewer.
    if (std::abs(along) < 0.5) {
      return ErrorMessage{"calibration platform joint " + std::to_string(i) + " (" + joint.name +
                          "): its axis is " + std::to_string(std::acos(std::abs(along)) / kDeg) +
                          " degrees off " + axis_names[i] + "; joints must be pan, tilt, roll"};
    }
    m.signs_[i] = along > 0 ? 1 : -1;
    m.radians_per_tick_[i] = joint.radians_per_tick;
    frame = frame * geometry::DhTransform(joint, 0.0);
  }
  return m;
}

PlatformTicks ViewerToPlatform::Ticks(const ViewerOrientation& v) const {
  PlatformTicks t;
  t.yaw = RoundTicks(signs_[0] * v.yaw_deg * kDeg, radians_per_tick_[0], kYawLimit);
  if (!all_axes_) return t;
  if (joints_ > 1)
    t.pitch = RoundTicks(signs_[1] * v.pitch_deg * kDeg, radians_per_tick_[1], kPitchRollLimit);
  if (joints_ > 2)
    t.roll = RoundTicks(signs_[2] * v.roll_deg * kDeg, radians_per_tick_[2], kPitchRollLimit);
  return t;
}

std::vector<double> ViewerToPlatform::JointAngles(const PlatformTicks& ticks) const {
  std::vector<double> q(joints_, 0.0);
  const int32_t t[3] = {ticks.yaw, ticks.pitch, ticks.roll};
  for (size_t i = 0; i < q.size() && i < 3; ++i) q[i] = t[i] * radians_per_tick_[i];
  return q;
}

PlatformTicks ViewerToPlatform::TicksOf(std::span<const double> joints_rad) const {
  PlatformTicks t;
  if (!joints_rad.empty()) t.yaw = RoundTicks(joints_rad[0], radians_per_tick_[0], kYawLimit);
  if (joints_rad.size() > 1)
    t.pitch = RoundTicks(joints_rad[1], radians_per_tick_[1], kPitchRollLimit);
  if (joints_rad.size() > 2)
    t.roll = RoundTicks(joints_rad[2], radians_per_tick_[2], kPitchRollLimit);
  return t;
}

ViewerOrientation ViewerZero::Apply(const ViewerOrientation& reading) const {
  if (identity_) return reading;
  return OrientationOf(offset_ * RotationOf(reading));
}

void ViewerZero::Rezero(const ViewerOrientation& session, const ViewerOrientation& first) {
  offset_ = RotationOf(session) * RotationOf(first).transpose();
  identity_ = false;
}

}  // namespace igms::control
