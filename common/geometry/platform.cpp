#include "common/geometry/platform.h"

#include <cmath>
#include <stdexcept>

#include "common/base/result.h"

namespace igms::geometry {
namespace {

void CheckSize(const PlatformModel& model, std::span<const double> values) {
  if (values.size() != model.joints.size()) {
    throw std::invalid_argument("platform: expected " + std::to_string(model.joints.size()) +
                                " joint values, got " + std::to_string(values.size()));
  }
}

}  // namespace

bool PlatformModel::Check(std::string* error) const {
  if (joints.empty() || joints.size() > 6) return Fail(error, "platform needs 1 to 6 joints");
  for (size_t i = 0; i < joints.size(); ++i) {
    const DhJoint& j = joints[i];
    const std::string where = "joint " + std::to_string(i) + " (" + j.name + ")";
    if (!std::isfinite(j.theta_offset) || !std::isfinite(j.d) || !std::isfinite(j.a) ||
        !std::isfinite(j.alpha) || !std::isfinite(j.radians_per_tick)) {
      return Fail(error, where + ": parameter is not finite");
    }
    if (j.radians_per_tick == 0.0) return Fail(error, where + ": radians_per_tick is zero");
  }
  const Eigen::Matrix4d m = world_from_base.matrix();
  if (!m.allFinite()) return Fail(error, "world_from_base is not finite");
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-6 ||
      std::abs(R.determinant() - 1.0) > 1e-6 ||
      (m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-12) {
    return Fail(error,
                "world_from_base is not a rigid transform (rotation must be orthonormal, det +1)");
  }
  return true;
}

double ThesisPanDegreesPerTick() { return 360.0 / (4.0 * 1800.0 * 13.57); }
double ThesisTiltDegreesPerTick() { return 360.0 / (4.0 * 1000.0 * 5.14); }

PlatformModel ThesisPlatform(const Eigen::Vector3d& pan_axis_point, double tilt_height,
                             double pan_heading_radians) {
  constexpr double kDeg = M_PI / 180.0;
  PlatformModel model;
  model.world_from_base = Eigen::Translation3d(pan_axis_point) *
                          Eigen::AngleAxisd(pan_heading_radians, Eigen::Vector3d::UnitZ());
  // Pan about z0 (up); x1 along the heading; z1 (the tilt axis) horizontal.
  model.joints.push_back(
      {"pan", 0.0, tilt_height, 0.0, M_PI / 2, ThesisPanDegreesPerTick() * kDeg});
  // Tilt about z1; z2 (the roll axis) perpendicular to pan and tilt axes: the view direction.
  model.joints.push_back({"tilt", M_PI / 2, 0.0, 0.0, M_PI / 2, ThesisTiltDegreesPerTick() * kDeg});
  model.joints.push_back({"roll", 0.0, 0.0, 0.0, 0.0, ThesisTiltDegreesPerTick() * kDeg});
  return model;
}

Eigen::Isometry3d DhTransform(const DhJoint& j, double q) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.rotate(Eigen::AngleAxisd(j.theta_offset + q, Eigen::Vector3d::UnitZ()));
  t.translate(Eigen::Vector3d(0.0, 0.0, j.d));
  t.translate(Eigen::Vector3d(j.a, 0.0, 0.0));
  t.rotate(Eigen::AngleAxisd(j.alpha, Eigen::Vector3d::UnitX()));
  return t;
}

Eigen::Isometry3d WorldFromEnd(const PlatformModel& model, std::span<const double> q) {
  CheckSize(model, q);
  Eigen::Isometry3d t = model.world_from_base;
  for (size_t i = 0; i < q.size(); ++i) t = t * DhTransform(model.joints[i], q[i]);
  return t;
}

std::vector<double> AnglesFromTicks(const PlatformModel& model, std::span<const double> ticks) {
  CheckSize(model, ticks);
  std::vector<double> q(ticks.size());
  for (size_t i = 0; i < ticks.size(); ++i) q[i] = ticks[i] * model.joints[i].radians_per_tick;
  return q;
}

Eigen::Isometry3d WorldMotion(const PlatformModel& model, std::span<const double> q) {
  const std::vector<double> zero(model.joints.size(), 0.0);
  return WorldFromEnd(model, q) * WorldFromEnd(model, zero).inverse();
}

Matrix34 CameraAtPose(const Matrix34& P0, const PlatformModel& model, std::span<const double> q) {
  return P0 * WorldMotion(model, q).inverse().matrix();
}

}  // namespace igms::geometry
