#include "object_server/ranger.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace igms::object {

std::optional<RangerPose> RangerInWorld(const calibration::StereoCalibration& cal,
                                        std::span<const double> q) {
  if (!cal.ranger) return std::nullopt;
  return geometry::RangerBeamAt(cal.ranger->origin, cal.ranger->axis, cal.platform, q);
}

std::vector<Eigen::Vector3d> CylinderSurface(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                             double radius, double spacing) {
  std::vector<Eigen::Vector3d> out;
  Eigen::Vector3d w = p1 - p0;
  const double height = w.norm();
  if (height < 1e-9 || radius <= 0 || spacing <= 0) return out;
  w /= height;
  const Eigen::Vector3d u = w.unitOrthogonal(), v = w.cross(u);
  const int around = std::clamp(static_cast<int>(std::ceil(2 * M_PI * radius / spacing)), 8, 720);
  const int along = std::clamp(static_cast<int>(std::ceil(height / spacing)), 1, 2000);
  const int rings = std::clamp(static_cast<int>(std::ceil(radius / spacing)), 1, 200);
  for (int i = 0; i < around; ++i) {
    const double a = 2 * M_PI * i / around;
    const Eigen::Vector3d dir = std::cos(a) * u + std::sin(a) * v;
    for (int j = 0; j <= along; ++j) out.push_back(p0 + (height * j / along) * w + radius * dir);
    for (int k = 0; k < rings; ++k)  // the caps
      for (const Eigen::Vector3d& c : {p0, p1}) out.push_back(c + (radius * k / rings) * dir);
  }
  return out;
}

std::vector<Eigen::Vector3d> BoxSurface(const Eigen::Vector3d& min, const Eigen::Vector3d& max,
                                        double spacing) {
  std::vector<Eigen::Vector3d> out;
  if (spacing <= 0) return out;
  const Eigen::Vector3d size = max - min;
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    const int na = std::clamp(static_cast<int>(std::ceil(size[a] / spacing)), 1, 2000);
    const int nb = std::clamp(static_cast<int>(std::ceil(size[b] / spacing)), 1, 2000);
    for (const double side : {min[axis], max[axis]})
      for (int i = 0; i <= na; ++i)
        for (int j = 0; j <= nb; ++j) {
          Eigen::Vector3d p;
          p[axis] = side;
          p[a] = min[a] + size[a] * i / na;
          p[b] = min[b] + size[b] * j / nb;
          out.push_back(p);
        }
  }
  return out;
}

std::optional<BeamRanges> RangesInBeam(const std::vector<Eigen::Vector3d>& surface,
                                       const RangerPose& ranger, double half_angle_rad,
                                       double spacing) {
  const double cos_half = std::cos(half_angle_rad);
  double nearest = std::numeric_limits<double>::infinity();
  double on_axis = -1;
  for (const Eigen::Vector3d& p : surface) {
    const Eigen::Vector3d d = p - ranger.origin;
    const double dist = d.norm(), along = d.dot(ranger.axis);
    if (dist < 1e-9 || along < cos_half * dist) continue;
    nearest = std::min(nearest, dist);
    // Within a sample spacing of the axis: where the axis meets the solid (the nearest such).
    if ((d - along * ranger.axis).norm() <= spacing && (on_axis < 0 || along < on_axis))
      on_axis = along;
  }
  if (!std::isfinite(nearest)) return std::nullopt;
  return BeamRanges{nearest, on_axis < 0 ? nearest : std::max(nearest, on_axis)};
}

}  // namespace igms::object
