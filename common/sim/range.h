// What the ultrasonic ranger would measure (Cooke, section 2.1.5): the distance to the
// nearest surface inside a beam cone. Used by the ranger's simulator.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "common/sim/scene.h"

namespace igms::site {

// Distance along a unit ray to the first surface (solids and the table top), or nullopt
// when the ray leaves the scene. `direction` need not be unit length.
std::optional<double> CastRay(const Scene& scene, const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& direction);

// The nearest surface distance over a cone of half angle `half_angle` (radians) around
// `axis` from `origin`, sampled on `rings` concentric rings (plus the axis itself) of
// 6 * ring rays each. half_angle = 0 is CastRay along the axis. nullopt when nothing is hit.
std::optional<double> RangeInCone(const Scene& scene, const Eigen::Vector3d& origin,
                                  const Eigen::Vector3d& axis, double half_angle, int rings = 12);

}  // namespace igms::site
