#include "device_daemons/viewer/pose_tracker.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace igms::devices {

namespace {

constexpr double kDeg = M_PI / 180.0;

double RoundTo(double value, double step) {
  return step > 0 ? std::round(value / step) * step : value;
}

double Wrap180(double deg) {
  deg = std::fmod(deg + 180.0, 360.0);
  if (deg < 0) deg += 360.0;
  return deg - 180.0;
}

}  // namespace

Eigen::Matrix3d RotationFromYpr(double yaw_deg, double pitch_deg, double roll_deg) {
  return (Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch_deg * kDeg, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll_deg * kDeg, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d YprFromRotation(const Eigen::Matrix3d& r) {
  // R(2,0) = -sin(pitch); near +-1 the yaw and roll axes coincide.
  const double s = std::clamp(-r(2, 0), -1.0, 1.0);
  const double pitch = std::asin(s);
  if (std::abs(s) > 1 - 1e-12) {
    const double yaw = std::atan2(-r(0, 1), r(1, 1));
    return {Wrap180(yaw / kDeg), pitch / kDeg, 0.0};
  }
  const double yaw = std::atan2(r(1, 0), r(0, 0));
  const double roll = std::atan2(r(2, 1), r(2, 2));
  return {Wrap180(yaw / kDeg), pitch / kDeg, Wrap180(roll / kDeg)};
}

bool PoseTrackerOptions::Check(std::string* error) const {
  const auto fail = [error](const std::string& why) {
    if (error) *error = "pose tracker: " + why;
    return false;
  };
  if (!(position_step_m >= 0) || !std::isfinite(position_step_m))
    return fail("position_step_m must be >= 0");
  if (!(angle_step_deg >= 0) || !std::isfinite(angle_step_deg))
    return fail("angle_step_deg must be >= 0");
  if (!(position_range_m > 0) || !std::isfinite(position_range_m))
    return fail("position_range_m must be > 0");
  if (!(site_units_per_metre > 0) || !std::isfinite(site_units_per_metre)) {
    return fail("site_units_per_metre must be > 0");
  }
  const Eigen::Matrix3d r = site_from_power_up.linear();
  if (!site_from_power_up.matrix().allFinite() ||
      !(r.transpose() * r).isApprox(Eigen::Matrix3d::Identity(), 1e-6) || r.determinant() < 0) {
    return fail("site_from_power_up must be a rigid transform");
  }
  return true;
}

PoseTracker::PoseTracker(PoseTrackerOptions options) : options_(std::move(options)) {
  std::string error;
  if (!options_.Check(&error)) throw std::invalid_argument(error);
}

TrackerReading PoseTracker::Read(const Eigen::Isometry3d& site_from_head) const {
  const Eigen::Isometry3d relative = options_.site_from_power_up.inverse() * site_from_head;
  TrackerReading out;
  const double range = options_.position_range_m;
  for (int i = 0; i < 3; ++i) {
    double metres = relative.translation()[i] / options_.site_units_per_metre;
    if (std::abs(metres) > range) {
      out.clamped = true;
      metres = std::clamp(metres, -range, range);
    }
    out.position_m[i] = RoundTo(metres, options_.position_step_m);
  }
  const Eigen::Vector3d ypr = YprFromRotation(relative.linear());
  for (int i = 0; i < 3; ++i) out.ypr_deg[i] = RoundTo(ypr[i], options_.angle_step_deg);
  // Rounding may carry yaw or roll to +180: keep them in [-180, 180).
  out.ypr_deg[0] = Wrap180(out.ypr_deg[0]);
  out.ypr_deg[2] = Wrap180(out.ypr_deg[2]);
  return out;
}

Eigen::Isometry3d PoseTracker::HeadInSite(const TrackerReading& reading) const {
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();
  relative.linear() = RotationFromYpr(reading.ypr_deg[0], reading.ypr_deg[1], reading.ypr_deg[2]);
  relative.translation() = reading.position_m * options_.site_units_per_metre;
  return options_.site_from_power_up * relative;
}

Eigen::Isometry3d HeadPoseFromMetres(const Eigen::Vector3d& position_m,
                                     const Eigen::Vector3d& ypr_deg, double site_units_per_metre) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = RotationFromYpr(ypr_deg[0], ypr_deg[1], ypr_deg[2]);
  pose.translation() = position_m * site_units_per_metre;
  return pose;
}

}  // namespace igms::devices
