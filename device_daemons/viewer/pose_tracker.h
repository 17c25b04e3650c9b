// What a head tracker (the thesis's Fakespace BOOM2C, Cooke, "Interactive Graphical Model
// Building using Virtual Reality", section 2.1.3) reports for a head pose in the site.
//
// Frames and units: a head pose is site_from_head, a rigid transform in the site's frame
// and units (inches for the thesis's testbed; z up). The head frame is x forward, y left,
// z up. The tracker reports the head's pose relative to its power-up pose, as the BOOM did:
//     relative = site_from_power_up^-1 * site_from_head
// its translation in metres along the power-up head's axes, its rotation as yaw, pitch,
// roll in degrees with R = Rz(yaw) Ry(pitch) Rx(roll) (yaw applied first, about the
// power-up z; then pitch about the turned y, positive nose down; then roll about the
// turned x). Yaw and roll are in [-180, 180), pitch in [-90, 90].
//
// Resolution: the reading is rounded to the tracker's steps, the BOOM's protocol by
// default (0.5 mm, 360/8192 degree: device_daemons/viewer/boom_protocol.h), and positions
// are clamped to its range (+-1.0235 m), with `clamped` set when they were.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

namespace igms::devices {

// R = Rz(yaw) Ry(pitch) Rx(roll), angles in degrees.
Eigen::Matrix3d RotationFromYpr(double yaw_deg, double pitch_deg, double roll_deg);
// The inverse: (yaw, pitch, roll) in degrees, ranges as above. At pitch +-90 degrees (gimbal
// lock) roll is 0 and yaw takes the whole turn about z.
Eigen::Vector3d YprFromRotation(const Eigen::Matrix3d& rotation);

struct PoseTrackerOptions {
  Eigen::Isometry3d site_from_power_up = Eigen::Isometry3d::Identity();
  double site_units_per_metre = 1.0 / 0.0254;  // inches
  double position_step_m = 0.0005;             // 0 = no rounding
  double angle_step_deg = 360.0 / 8192.0;      // 0 = no rounding
  double position_range_m = 1.0235;            // |x|, |y|, |z| at most this
  // Steps >= 0, range and units > 0, finite, a rigid power-up pose.
  bool Check(std::string* error) const;
};

struct TrackerReading {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d ypr_deg = Eigen::Vector3d::Zero();  // yaw, pitch, roll
  bool clamped = false;                               // a position was outside the tracker's range
};

class PoseTracker {
 public:
  // Options must pass Check (std::invalid_argument otherwise).
  explicit PoseTracker(PoseTrackerOptions options = {});

  // What the tracker reports for a head at site_from_head.
  TrackerReading Read(const Eigen::Isometry3d& site_from_head) const;
  // The head pose in the site a reading stands for (exact for an unclamped reading up to
  // the rounding: the round trip moves a point 1 m ahead of the head by less than
  // position_step + angle_step in radians, in metres).
  Eigen::Isometry3d HeadInSite(const TrackerReading& reading) const;

  const PoseTrackerOptions& options() const { return options_; }

 private:
  PoseTrackerOptions options_;
};

// A head pose in the site from a position in metres and yaw, pitch, roll in degrees, both
// in the site's axes (the form of the viewer simulator's path file), in the site's units.
Eigen::Isometry3d HeadPoseFromMetres(const Eigen::Vector3d& position_m,
                                     const Eigen::Vector3d& ypr_deg, double site_units_per_metre);

}  // namespace igms::devices
