// Synthetic cameras for tests: a pinhole looking from a centre at a target, and the thesis-like
// stereo rig (two cameras 4 inches apart, 6 inches above the table, looking along +x at
// objects 3 to 7 feet away). Ground truth for projecting and recovering points.
#pragma once

#include <Eigen/Dense>
#include <random>

#include "common/geometry/camera.h"

namespace igms::testing {

inline Eigen::Matrix3d Intrinsics(double f, double cx, double cy, double aspect = 1.0) {
  Eigen::Matrix3d K;
  K << f, 0, cx, 0, f * aspect, cy, 0, 0, 1;
  return K;
}

// camera_from_world rotation with z forward (towards target), x right, y down, world z up.
inline Eigen::Matrix3d LookAtRotation(const Eigen::Vector3d& center, const Eigen::Vector3d& target,
                                      const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ()) {
  const Eigen::Vector3d z = (target - center).normalized();
  const Eigen::Vector3d x = z.cross(up).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R.row(0) = x.transpose();
  R.row(1) = y.transpose();
  R.row(2) = z.transpose();
  return R;
}

inline geometry::Matrix34 LookAt(const Eigen::Matrix3d& K, const Eigen::Vector3d& center,
                                 const Eigen::Vector3d& target) {
  const Eigen::Matrix3d R = LookAtRotation(center, target);
  geometry::Matrix34 Rt;
  Rt << R, -R * center;
  return K * Rt;
}

struct StereoRig {
  geometry::ProjectiveCamera left;
  geometry::ProjectiveCamera right;
};

// Thesis-like: 512x480, about 25 degrees field of view, baseline 4 along y, slight toe-in.
inline StereoRig ThesisLikeRig() {
  const Eigen::Matrix3d K = Intrinsics(1150.0, 255.5, 239.5, 1.02);
  const Eigen::Vector3d target(60, 0, 2);
  return {geometry::ProjectiveCamera(LookAt(K, {0, 2, 6}, target), {512, 480}),
          geometry::ProjectiveCamera(LookAt(K, {0, -2, 6}, target), {512, 480})};
}

// A random point on the table area the rig sees: x 36..84 in, y -6..6, z 0..10.
inline Eigen::Vector3d RandomScenePoint(std::mt19937& rng) {
  std::uniform_real_distribution<double> x(36, 84), y(-6, 6), z(0, 10);
  return {x(rng), y(rng), z(rng)};
}

}  // namespace igms::testing
