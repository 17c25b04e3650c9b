// The small stereo rig the object server's tests draw scenes for by hand: 256 x 192 pixels,
// focal length 400 px, each camera at (x, 0, 0) looking along the world's +y with z up.
#pragma once

#include <Eigen/Core>

#include "common/geometry/camera.h"

namespace igms::object::testing {

inline geometry::ProjectiveCamera RigCamera(double x) {
  Eigen::Matrix3d K, R;
  K << 400, 0, 127.5, 0, 400, 95.5, 0, 0, 1;
  R << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  geometry::Matrix34 P;
  P.leftCols<3>() = K * R;
  P.col(3) = -K * R * Eigen::Vector3d(x, 0, 0);
  return geometry::ProjectiveCamera(P, {256, 192});
}

}  // namespace igms::object::testing
