#include "common/sim/range.h"

#include <Eigen/Geometry>
#include <cmath>

namespace igms::site {

std::optional<double> CastRay(const Scene& scene, const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& direction) {
  const Eigen::Vector3d d = direction.normalized();
  std::optional<double> best;
  for (const auto& object : scene.objects) {
    if (auto hit = Intersect(object.shape, origin, d); hit && (!best || hit->t < *best))
      best = hit->t;
  }
  const Table& table = scene.table;
  if (table.enabled && origin.z() > 0 && d.z() < 0) {
    const double t = -origin.z() / d.z();
    const Eigen::Vector3d p = origin + t * d;
    if (p.x() >= table.x_min && p.x() <= table.x_max && p.y() >= table.y_min &&
        p.y() <= table.y_max && (!best || t < *best))
      best = t;
  }
  return best;
}

std::optional<double> RangeInCone(const Scene& scene, const Eigen::Vector3d& origin,
                                  const Eigen::Vector3d& axis, double half_angle, int rings) {
  const Eigen::Vector3d w = axis.normalized();
  std::optional<double> best = CastRay(scene, origin, w);
  if (half_angle <= 0 || rings <= 0) return best;
  const Eigen::Vector3d u = w.unitOrthogonal(), v = w.cross(u);
  for (int ring = 1; ring <= rings; ++ring) {
    const double theta = half_angle * ring / rings;
    const int count = 6 * ring;
    for (int k = 0; k < count; ++k) {
      const double phi = 2 * M_PI * k / count;
      const Eigen::Vector3d d =
          std::cos(theta) * w + std::sin(theta) * (std::cos(phi) * u + std::sin(phi) * v);
      if (auto t = CastRay(scene, origin, d); t && (!best || *t < *best)) best = t;
    }
  }
  return best;
}

}  // namespace igms::site
