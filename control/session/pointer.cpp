#include "control/session/pointer.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

#include "common/geometry/platform.h"

namespace igms::control {

std::optional<CameraFrame> CameraFrameOf(const geometry::ProjectiveCamera& camera) {
  CameraFrame f;
  f.center = camera.Center();
  f.forward = camera.ViewDirection();
  if (!f.center.allFinite() || !f.forward.allFinite()) return std::nullopt;
  // Move one pixel along u and along v from the optical axis, staying at the same depth.
  const double depth = 1.0;
  const Eigen::Vector3d on_axis = f.OnAxis(depth);
  const auto pixel = camera.Project(on_axis);
  if (!pixel) return std::nullopt;
  auto at_depth = [&](const Eigen::Vector2d& px) -> Eigen::Vector3d {
    const geometry::Ray ray = camera.PixelRay(px);
    return ray.At(depth / ray.direction.dot(f.forward));
  };
  Eigen::Vector3d right = at_depth(*pixel + Eigen::Vector2d(1, 0)) - on_axis;
  Eigen::Vector3d down = at_depth(*pixel + Eigen::Vector2d(0, 1)) - on_axis;
  right -= right.dot(f.forward) * f.forward;
  down -= down.dot(f.forward) * f.forward;
  if (!(right.norm() > 0) || !(down.norm() > 0)) return std::nullopt;
  // An orthonormal frame: the image's skew (a few thousandths for the thesis's cameras)
  // would otherwise couple the stick's axes.
  f.right = right.normalized();
  f.down = f.forward.cross(f.right);
  if (f.down.dot(down) < 0) f.down = -f.down;  // a mirrored image
  return f;
}

Beam BeamAt(const calibration::StereoCalibration& cal, std::span<const double> q) {
  Beam mount;
  std::optional<Eigen::Isometry3d> end_from_world_at_zero;
  if (cal.ranger) {
    mount.origin = cal.ranger->origin;
    mount.axis = cal.ranger->axis.normalized();
  } else {
    // Placed in the world at the zero pose; carried into the end frame below.
    const auto l = cal.left.Camera(), r = cal.right.Camera();
    mount.origin = 0.5 * (l.Center() + r.Center());
    mount.axis = (l.ViewDirection() + r.ViewDirection()).normalized();
    if (!cal.platform) return mount;
    const std::vector<double> zero(cal.platform->joints.size(), 0.0);
    end_from_world_at_zero = geometry::WorldFromEnd(*cal.platform, zero).inverse();
    mount.origin = *end_from_world_at_zero * mount.origin;
    mount.axis = end_from_world_at_zero->linear() * mount.axis;
  }
  if (!cal.platform) return mount;
  std::vector<double> angles(cal.platform->joints.size(), 0.0);
  std::copy_n(q.begin(), std::min(q.size(), angles.size()), angles.begin());
  const Eigen::Isometry3d world_from_end = geometry::WorldFromEnd(*cal.platform, angles);
  return {world_from_end * mount.origin, (world_from_end.linear() * mount.axis).normalized()};
}

bool CylinderContains(const object::CylinderModel& c, const Eigen::Vector3d& p) {
  Eigen::Vector3d axis = ToEigen(c.axis());
  if (!(axis.norm() > 0)) return false;
  axis.normalize();
  const Eigen::Vector3d d = p - ToEigen(c.center());
  const double along = d.dot(axis);
  return std::abs(along) <= c.height() / 2 && (d - along * axis).norm() <= c.radius();
}

bool BoxContains(const object::BoxModel& b, const Eigen::Vector3d& p) {
  const Eigen::Vector3d size = ToEigen(b.size());
  if (size.x() > 0 && size.y() > 0 && size.z() > 0) {
    const double yaw = b.yaw_deg() * M_PI / 180.0;
    const Eigen::Vector3d d = p - ToEigen(b.center());
    // Into the box's own axes: its x is (cos yaw, sin yaw, 0).
    const Eigen::Vector3d local(std::cos(yaw) * d.x() + std::sin(yaw) * d.y(),
                                -std::sin(yaw) * d.x() + std::cos(yaw) * d.y(), d.z());
    return (local.cwiseAbs() - size / 2).maxCoeff() <= 0;
  }
  const Eigen::Vector3d lo = ToEigen(b.min()), hi = ToEigen(b.max());
  return (p - lo).minCoeff() >= 0 && (hi - p).minCoeff() >= 0;
}

}  // namespace igms::control
