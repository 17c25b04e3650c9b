// A known site for the ranger tests: a calibration whose platform pans about a vertical
// axis through the sensor, the sensor 10 in above the floor looking along -y at the zero
// pose, a box straight ahead (its near face 48 in away) and a sphere 30 in away along the
// beam once the platform has panned by kPanDeg. No table, so nothing else echoes.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "common/calibration/calibration_file.h"
#include "common/geometry/platform.h"
#include "common/sim/testbed.h"

namespace igms::devices::testing {

inline constexpr double kBoxRangeIn = 48.0;
inline constexpr double kSphereRangeIn = 30.0;
inline constexpr double kPanDeg = 40.0;

inline const Eigen::Vector3d& SensorAtZero() {
  static const Eigen::Vector3d o(20, 0, 10);
  return o;
}

inline calibration::StereoCalibration TestCalibration() {
  calibration::StereoCalibration c;
  const site::StereoCameras cams = site::ThesisCameras();
  c.left.P = cams.left.P();
  c.left.image_size = cams.left.image_size();
  c.right.P = cams.right.P();
  c.right.image_size = cams.right.image_size();
  c.platform = geometry::ThesisPlatform(Eigen::Vector3d(20, 0, 0), 10.0, -M_PI / 2);
  // The mount is written in the end frame: the zero-pose world beam taken into it.
  const std::vector<double> zero(c.platform->joints.size(), 0.0);
  const Eigen::Isometry3d end_from_world = geometry::WorldFromEnd(*c.platform, zero).inverse();
  calibration::RangerCalibration r;
  r.origin = end_from_world * SensorAtZero();
  r.axis = end_from_world.linear() * Eigen::Vector3d(0, -1, 0);
  c.ranger = r;
  return c;
}

// Joint angles of a pan by `deg`, and the world direction of the beam there.
inline std::vector<double> PanAngles(double deg) { return {deg * M_PI / 180.0, 0.0, 0.0}; }
inline Eigen::Vector3d BeamDirection(double deg) {
  const auto c = TestCalibration();
  const auto q = PanAngles(deg);
  return geometry::WorldMotion(*c.platform, q).linear() * Eigen::Vector3d(0, -1, 0);
}

inline std::string TestSceneYaml() {
  const Eigen::Vector3d s = SensorAtZero() + (kSphereRangeIn + 3.0) * BeamDirection(kPanDeg);
  std::ostringstream y;
  y.precision(12);
  y << "table: {enabled: false}\n"
    << "objects:\n"
    << "  - {name: ahead, type: box, center: [20, " << -(kBoxRangeIn + 2)
    << ", 10], size: [8, 4, 8]}\n"
    << "  - {name: aside, type: sphere, center: [" << s.x() << ", " << s.y() << ", " << s.z()
    << "], radius: 3}\n";
  return y.str();
}

}  // namespace igms::devices::testing
