// The viewer's orientation as the camera platform's, in encoder ticks (Cooke, *Interactive
// Graphical Model Building using Virtual Reality*, sections 2.1.3, 2.1.7, 2.4, 4.4).
//
// In verification the platform is slaved to the viewer: the head's rotation from its
// power-up pose becomes the same rotation of the cameras from the platform's zero pose.
// The viewer reports yaw, pitch, roll with R = Rz(yaw) Ry(pitch) Rx(roll) in its power-up
// frame (x forward, y left, z up): positive yaw turns left, positive pitch is nose DOWN,
// positive roll turns about the forward axis. The platform's joints (pan, tilt, roll, in the
// calibration's Denavit-Hartenberg model, common/geometry/platform.h) turn about their own
// axes, whose directions the calibration fixes: the thesis's head tilts positive looking UP.
// So each joint's sign comes from its axis at the zero pose against the cameras' frame:
//   pan  = +yaw   * sign(pan axis . up)              up = the world's +z
//   tilt = +pitch * sign(tilt axis . left)           left = up x forward, level
//   roll = +roll  * sign(roll axis . forward)        forward = the left camera's optical
//                                                    axis at the zero pose
// and ticks = angle / radians_per_tick, rounded, held inside the protocol's range (yaw
// +-1048575, pitch and roll +-8191; the platform stops at its own mechanical limits).
// Without a platform model the thesis's tick scales (4.4) and signs (+, -, +) are used.
// Pan only, as in the thesis, unless all three axes are asked for.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/calibration/calibration_file.h"

namespace igms::control {

struct PlatformTicks {
  int32_t yaw = 0;
  int32_t pitch = 0;
  int32_t roll = 0;
  bool operator==(const PlatformTicks&) const = default;
};

struct ViewerOrientation {
  double yaw_deg = 0.0;
  double pitch_deg = 0.0;  // positive nose down
  double roll_deg = 0.0;
};

// R = Rz(yaw) Ry(pitch) Rx(roll) and back (yaw, roll in (-180, 180], pitch in [-90, 90]).
Eigen::Matrix3d RotationOf(const ViewerOrientation& o);
ViewerOrientation OrientationOf(const Eigen::Matrix3d& R);

class ViewerToPlatform {
 public:
  // An error when a joint's axis is not near the camera axis it should turn about (a
  // calibration whose joints are not pan, tilt, roll in that order).
  static Result<ViewerToPlatform> Make(const calibration::StereoCalibration& calibration,
                                       bool all_axes);

  PlatformTicks Ticks(const ViewerOrientation& viewer) const;
  // Joint angles (radians) of a pose in ticks, one per joint of the model (at most three
  // from ticks; further joints zero). Without a model: pan, tilt, roll.
  std::vector<double> JointAngles(const PlatformTicks& ticks) const;
  // The ticks of joint angles (a grab's pose), rounded.
  PlatformTicks TicksOf(std::span<const double> joints_rad) const;

  // +1 or -1 per axis (pan, tilt, roll): platform angle = sign * viewer angle.
  const std::array<int, 3>& signs() const { return signs_; }
  const std::array<double, 3>& radians_per_tick() const { return radians_per_tick_; }
  bool all_axes() const { return all_axes_; }

 private:
  std::array<int, 3> signs_{1, -1, 1};
  std::array<double, 3> radians_per_tick_{};
  size_t joints_ = 3;
  bool all_axes_ = false;
};

// Keeps the session's viewer orientation continuous across a restarted viewer daemon,
// whose readings start again from a new zero: after Rezero, Apply maps the new daemon's
// orientation so that its first reading equals the orientation the session had.
class ViewerZero {
 public:
  ViewerOrientation Apply(const ViewerOrientation& reading) const;
  // `session` is the orientation the session last used, `first` the new daemon's reading.
  void Rezero(const ViewerOrientation& session, const ViewerOrientation& first);
  bool identity() const { return identity_; }

 private:
  Eigen::Matrix3d offset_ = Eigen::Matrix3d::Identity();
  bool identity_ = true;
};

}  // namespace igms::control
