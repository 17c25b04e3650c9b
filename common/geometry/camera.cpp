#include "common/geometry/camera.h"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

#include "common/geometry/distortion.h"

namespace igms::geometry {

ProjectiveCamera::ProjectiveCamera(const Matrix34& P, ImageSize size) : P_(P), size_(size) {}

ProjectiveCamera::ProjectiveCamera(const Matrix34& P, ImageSize size, Lens lens)
    : P_(P), size_(size), lens_(std::move(lens)) {
  std::string why;
  if (!CheckDistortion(lens_->dist, &why)) throw std::invalid_argument(why);
  if (!(std::abs(lens_->K.determinant()) > 0) || !lens_->K.allFinite()) {
    throw std::invalid_argument("lens K is not invertible");
  }
}

bool ProjectiveCamera::has_distortion() const {
  if (!lens_) return false;
  for (double c : lens_->dist) {
    if (c != 0.0) return true;
  }
  return false;
}

std::optional<Eigen::Vector2d> ProjectiveCamera::Project(const Eigen::Vector3d& world) const {
  const Eigen::Vector3d x = P_ * world.homogeneous();
  if (std::abs(x.z()) < 1e-12 * x.head<2>().norm() || x.z() == 0.0) return std::nullopt;
  return x.hnormalized();
}

std::optional<Eigen::Vector2d> ProjectiveCamera::ProjectObserved(
    const Eigen::Vector3d& world) const {
  auto ideal = Project(world);
  if (!ideal) return std::nullopt;
  return Distort(*ideal);
}

Eigen::Vector2d ProjectiveCamera::Distort(const Eigen::Vector2d& ideal) const {
  if (!has_distortion()) return ideal;
  const Eigen::Vector2d x = lens_->K.partialPivLu().solve(ideal.homogeneous()).hnormalized();
  return (lens_->K * DistortNormalized(x, lens_->dist).homogeneous()).hnormalized();
}

std::optional<Eigen::Vector2d> ProjectiveCamera::Undistort(const Eigen::Vector2d& observed) const {
  if (!has_distortion()) return observed;
  const Eigen::Vector2d xd = lens_->K.partialPivLu().solve(observed.homogeneous()).hnormalized();
  auto x = UndistortNormalized(xd, lens_->dist);
  if (!x) return std::nullopt;
  return (lens_->K * x->homogeneous()).hnormalized();
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

Eigen::Vector3d ProjectiveCamera::ViewDirection() const {
  const Eigen::Matrix3d M = P_.leftCols<3>();
  const double sign = M.determinant() < 0 ? -1.0 : 1.0;
  return sign * M.row(2).transpose().normalized();
}

Ray ProjectiveCamera::PixelRay(const Eigen::Vector2d& pixel) const {
  const Eigen::Matrix3d M = P_.leftCols<3>();
  Eigen::Vector3d d = M.partialPivLu().solve(pixel.homogeneous());
  // Orient the ray so that points along it have positive depth.
  if (d.dot(ViewDirection()) < 0) d = -d;
  return {Center(), d.normalized()};
}

bool ProjectiveCamera::InImage(const Eigen::Vector2d& p, double margin) const {
  return p.x() >= -0.5 + margin && p.y() >= -0.5 + margin && p.x() <= size_.width - 0.5 - margin &&
         p.y() <= size_.height - 0.5 - margin;
}

}  // namespace igms::geometry
