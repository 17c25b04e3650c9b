// The camera platform (Cooke, section 3.4): a pan-tilt-roll head modelled as an open
// Denavit-Hartenberg chain, with both cameras rigidly on its last link.
//
// Frames: world (the site's), base (frame 0 of the chain, placed in the world by
// world_from_base), then one frame per joint. Joint i (1-based) rotates about z_{i-1}; its
// link transform is standard DH:
//     A_i(q_i) = Rot_z(theta_offset_i + q_i) Trans_z(d_i) Trans_x(a_i) Rot_x(alpha_i)
// and world_from_end(q) = world_from_base A_1(q_1) ... A_n(q_n). Joint angles q are in
// radians; q = 0 is the pose with every encoder at zero, q_i = ticks_i * radians_per_tick_i.
//
// A camera's P is calibrated at q = 0 (the calibration file's P). At pose q the camera has
// moved with the end link by the world-frame motion
//     world_motion(q) = world_from_end(q) world_from_end(0)^-1
// so its projection matrix is P(q) = P(0) world_motion(q)^-1. Only the joint axes (as world
// lines at q = 0) and the tick scales affect P(q); the offsets theta_offset_i and the last
// link's d, a, alpha cancel, and calibration holds them fixed.
//
// Thesis 4.4: the yaw (pan) encoder has 1800 ticks a quadrant through a 13.57 gear,
// 3.684e-3 degrees a tick; pitch (tilt) and roll 1000 ticks a quadrant through 5.14,
// 1.750e-2 degrees a tick. ThesisPlatform() builds a nominal model with those scales.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <span>
#include <string>
#include <vector>

#include "common/geometry/camera.h"

namespace igms::geometry {

struct DhJoint {
  std::string name;           // "pan", "tilt", "roll"
  double theta_offset = 0.0;  // radians
  double d = 0.0;             // world units, along z_{i-1}
  double a = 0.0;             // world units, along x_i
  double alpha = 0.0;         // radians, about x_i
  double radians_per_tick = 1.0;
};

struct PlatformModel {
  Eigen::Isometry3d world_from_base = Eigen::Isometry3d::Identity();
  std::vector<DhJoint> joints;

  // 1 to 6 joints, every number finite, every tick scale non-zero, world_from_base a
  // proper rigid transform (orthonormal rotation, det +1, within 1e-6).
  bool Check(std::string* error) const;
};

// Degrees per tick of thesis 4.4 (exact from the encoder counts and gear ratios).
double ThesisPanDegreesPerTick();   // 360 / (4 * 1800 * 13.57)
double ThesisTiltDegreesPerTick();  // 360 / (4 * 1000 * 5.14), also roll

// A nominal pan-tilt-roll head in the thesis's configuration: pan about world z through
// `pan_axis_point`, tilt about a horizontal axis `tilt_height` above it, roll about the
// axis perpendicular to both, with the thesis's tick scales. Useful as a starting point
// for calibration and for the simulated site.
PlatformModel ThesisPlatform(const Eigen::Vector3d& pan_axis_point, double tilt_height,
                             double pan_heading_radians);

// The DH link transform A_i(q).
Eigen::Isometry3d DhTransform(const DhJoint& joint, double q);

// world_from_end at joint angles q (size must equal the joint count).
Eigen::Isometry3d WorldFromEnd(const PlatformModel& model, std::span<const double> q);

// Joint angles in radians from encoder ticks (size must equal the joint count).
std::vector<double> AnglesFromTicks(const PlatformModel& model, std::span<const double> ticks);

// world_from_end(q) world_from_end(0)^-1: how the cameras moved, in world coordinates.
Eigen::Isometry3d WorldMotion(const PlatformModel& model, std::span<const double> q);

// The projection matrix at joint angles q of a camera whose matrix at q = 0 is P0.
Matrix34 CameraAtPose(const Matrix34& P0, const PlatformModel& model, std::span<const double> q);

}  // namespace igms::geometry
