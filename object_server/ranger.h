// The ultrasonic range as a depth constraint and as a check on the stereo result (Cooke,
// section 2.1.5, table 2.3: a 12-degree beam, so 0.208 m wide at 1 m).
//
// The ranger reports the distance to the nearest surface inside its beam, a cone of half
// angle `half_angle` around its axis. Before locating, the range gives the object's front
// depth if the point `origin + range * axis` falls inside the marked region; after, the
// located solid predicts which ranges the beam may report (RangeCheck in locate.h).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>
#include <vector>

#include "common/calibration/calibration_file.h"
#include "common/geometry/ranger_beam.h"

namespace igms::object {

// The beam's origin and unit axis in the world (common/geometry/ranger_beam.h).
using RangerPose = geometry::RangerBeam;

// The ranger of the calibration (its `ranger` map, in the platform's end frame) in the world
// at joint angles `q` (radians; empty = every joint at zero), by geometry::RangerBeamAt.
// Without a platform model the end frame is the world. nullopt when the calibration has no
// ranger.
std::optional<RangerPose> RangerInWorld(const calibration::StereoCalibration& calibration,
                                        std::span<const double> q = {});

// Points on a solid's surface, about `spacing` apart (world units), for the beam test:
// a cylinder (both cap centres p0, p1 and radius) or a world-axis-aligned box.
std::vector<Eigen::Vector3d> CylinderSurface(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                             double radius, double spacing);
std::vector<Eigen::Vector3d> BoxSurface(const Eigen::Vector3d& min, const Eigen::Vector3d& max,
                                        double spacing);

// The ranges the beam may report for a solid given by surface points: the nearest point
// inside the cone and the nearest point within `spacing` of the axis (its far end; the
// nearest in the cone when the axis misses). nullopt when no point is inside the cone.
struct BeamRanges {
  double nearest = 0, on_axis = 0;
};
std::optional<BeamRanges> RangesInBeam(const std::vector<Eigen::Vector3d>& surface,
                                       const RangerPose& ranger, double half_angle_rad,
                                       double spacing);

}  // namespace igms::object
