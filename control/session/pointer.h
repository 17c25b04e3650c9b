// The 3D pointer's geometry at a grab (Cooke, *Interactive Graphical Model Building using
// Virtual Reality*, sections 2.1.4, 2.1.5, 2.4, 4.3): the left camera's frame the stick
// moves it in, the ultrasonic beam the range command puts it on, and which stored model
// it is inside. World units are the calibration's (inches for the thesis's testbed).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>

#include "common/calibration/calibration_file.h"
#include "common/geometry/camera.h"
#include "igms/object.pb.h"

namespace igms::control {

// A camera's axes in the world, orthonormal: `forward` its optical axis into the scene,
// `right` the direction that moves a point on the optical axis along the image's +u at
// constant depth, `down` perpendicular to both, on the image's +v side.
struct CameraFrame {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d right = Eigen::Vector3d::UnitX();
  Eigen::Vector3d down = Eigen::Vector3d::UnitY();
  Eigen::Vector3d forward = Eigen::Vector3d::UnitZ();

  Eigen::Vector3d up() const { return -down; }
  // The point on the optical axis at `depth`.
  Eigen::Vector3d OnAxis(double depth) const { return center + depth * forward; }
};

// nullopt when P projects the optical axis nowhere finite (not a loaded calibration's P).
std::optional<CameraFrame> CameraFrameOf(const geometry::ProjectiveCamera& camera);

// The ultrasonic beam in the world.
struct Beam {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // unit
};

// The beam at joint angles q (radians; missing joints zero): the calibration's `ranger`
// mount (the platform's end frame) moved by world_from_end(q); without a `ranger` map the
// sensor sits midway between the camera centres looking along their mean optical axis at
// the zero pose (as the ranger simulator places it, docs/devices.md); without a platform
// model the beam does not move.
Beam BeamAt(const calibration::StereoCalibration& calibration, std::span<const double> q);

// Whether a point lies inside a located solid (the cylinder of its centre, axis, radius and
// height; the box of its oriented centre, size and yaw, or else its world-aligned min/max).
bool CylinderContains(const object::CylinderModel& cylinder, const Eigen::Vector3d& p);
bool BoxContains(const object::BoxModel& box, const Eigen::Vector3d& p);

inline Eigen::Vector3d ToEigen(const object::Vec3& v) { return {v.x(), v.y(), v.z()}; }
inline object::Vec3 ToVec3(const Eigen::Vector3d& v) {
  object::Vec3 out;
  out.set_x(v.x());
  out.set_y(v.y());
  out.set_z(v.z());
  return out;
}

}  // namespace igms::control
