// The ultrasonic ranger's beam in the world at a platform pose (Cooke, *Interactive Graphical
// Model Building using Virtual Reality*, section 2.1.5): the one computation the ranger
// simulator, the object server and the control client share.
//
// The sensor is mounted on the camera platform: its origin and axis are given in the
// platform's end frame (the calibration file's `ranger` map). At joint angles q
//     origin(q) = world_from_end(q) origin_end,   axis(q) = R_world_from_end(q) axis_end
// (platform.h), the same motion the cameras make. Without a platform model the end frame is
// the world frame and the beam never moves.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>

#include "common/geometry/platform.h"

namespace igms::geometry {

struct RangerBeam {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // world units, world frame
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();   // world frame, unit length
};

// The beam of a sensor at `origin_end` looking along `axis_end` (end frame; any non-zero
// length) at joint angles `q` in radians, in the model's joint order. Missing angles count
// as zero (an empty q is the zero pose) and extra ones are ignored; without a platform
// model q is ignored.
RangerBeam RangerBeamAt(const Eigen::Vector3d& origin_end, const Eigen::Vector3d& axis_end,
                        const std::optional<PlatformModel>& platform, std::span<const double> q);

}  // namespace igms::geometry
