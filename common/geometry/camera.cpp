#include "common/geometry/camera.h"

#include <Eigen/Dense>
#include <cmath>

namespace igms::geometry {

ProjectiveCamera::ProjectiveCamera(const Matrix34& P, ImageSize size) : P_(P), size_(size) {}

std::optional<Eigen::Vector2d> ProjectiveCamera::Project(const Eigen::Vector3d& world) const {
  const Eigen::Vector3d x = P_ * world.homogeneous();
  if (std::abs(x.z()) < 1e-12) return std::nullopt;
  return x.hnormalized();
}

double ProjectiveCamera::Depth(const Eigen::Vector3d& world) const {
  // Hartley & Zisserman, result 6.15: depth = sign(det M) * w / (|T| * m3 norm), with T = 1.
  const Eigen::Matrix3d M = P_.leftCols<3>();
  const double w = P_.row(2).dot(world.homogeneous());
  const double sign = M.determinant() < 0 ? -1.0 : 1.0;
  return sign * w / M.row(2).norm();
}

Eigen::Vector3d ProjectiveCamera::Center() const {
  const Eigen::Matrix3d M = P_.leftCols<3>();
  return -M.partialPivLu().solve(P_.col(3));
}

Ray ProjectiveCamera::PixelRay(const Eigen::Vector2d& pixel) const {
  const Eigen::Matrix3d M = P_.leftCols<3>();
  Eigen::Vector3d d = M.partialPivLu().solve(pixel.homogeneous());
  // Orient the ray so that points along it have positive depth.
  if (M.determinant() * d.dot(M.row(2).transpose()) < 0) d = -d;
  return {Center(), d.normalized()};
}

bool ProjectiveCamera::InImage(const Eigen::Vector2d& p, double margin) const {
  return p.x() >= -0.5 + margin && p.y() >= -0.5 + margin && p.x() <= size_.width - 0.5 - margin &&
         p.y() <= size_.height - 0.5 - margin;
}

}  // namespace igms::geometry
