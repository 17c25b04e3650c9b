// What the simulated ranger sees: a stand-in scene of planes, upright cylinders and
// axis-aligned boxes in the site's frame (z up, inches), and the sensor's pose. Range() is
// the nearest surface inside the beam cone along the sensor axis.
//
// The beam is sampled by rays: the axis and rings at 1/3, 2/3 and 3/3 of the half-angle
// (6 degrees), 12 rays a ring. The sensor's axis is +x of its frame turned by yaw about z,
// then pitch about the turned y (positive pitch looks up), from `origin_in`.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace igms::devices {

struct RangerScene {
  struct Plane {
    Eigen::Vector3d point, normal;
  };
  struct Cylinder {
    Eigen::Vector3d base;  // centre of the bottom face
    double radius, height;
  };
  struct Box {
    Eigen::Vector3d min, max;
  };
  std::vector<Plane> planes;
  std::vector<Cylinder> cylinders;
  std::vector<Box> boxes;

  // The default: a table top 30 in below the sensor, a wall at 10 ft, an upright cylinder
  // (radius 3 in, 12 in tall) 4 ft ahead and a block 5 ft ahead, 2 ft to the left.
  static RangerScene Testbed();
};

struct RangerPose {
  Eigen::Vector3d origin_in = Eigen::Vector3d::Zero();
  double yaw_deg = 0, pitch_deg = 0;
};

// Distance along one ray to the nearest surface, if any.
std::optional<double> CastRay(const RangerScene& scene, const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& direction);
// Nearest surface inside the beam (see above), without noise.
std::optional<double> BeamRange(const RangerScene& scene, const RangerPose& pose,
                                double beam_width_deg = 12.0);

}  // namespace igms::devices
