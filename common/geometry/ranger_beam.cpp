#include "common/geometry/ranger_beam.h"

#include <algorithm>
#include <vector>

namespace igms::geometry {

RangerBeam RangerBeamAt(const Eigen::Vector3d& origin_end, const Eigen::Vector3d& axis_end,
                        const std::optional<PlatformModel>& platform, std::span<const double> q) {
  RangerBeam beam{origin_end, axis_end.normalized()};
  if (!platform) return beam;
  std::vector<double> angles(platform->joints.size(), 0.0);
  std::copy_n(q.begin(), std::min(q.size(), angles.size()), angles.begin());
  const Eigen::Isometry3d world_from_end = WorldFromEnd(*platform, angles);
  beam.origin = world_from_end * origin_end;
  beam.axis = (world_from_end.linear() * axis_end).normalized();
  return beam;
}

}  // namespace igms::geometry
