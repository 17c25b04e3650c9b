#include "common/geometry/epipolar.h"

#include <Eigen/Dense>
#include <cmath>

#include "common/base/result.h"
#include "common/geometry/inverse_perspective.h"

namespace igms::geometry {
namespace {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

}  // namespace

Eigen::Matrix3d FundamentalMatrix(const Matrix34& from, const Matrix34& to) {
  const ProjectiveCamera a(from, {});
  const Eigen::Vector3d c = a.Center();
  if (!c.allFinite()) return Eigen::Matrix3d::Zero();
  const Eigen::Vector3d epipole = to * c.homogeneous();
  // Coincident centres: `to` sees from's centre as its own, and there is no baseline.
  if (!(epipole.norm() > 1e-10 * to.norm() * c.homogeneous().norm())) {
    return Eigen::Matrix3d::Zero();
  }
  // P^+ = P^T (P P^T)^-1 is a right inverse of `from`.
  const Eigen::Matrix<double, 4, 3> pinv = from.transpose() * (from * from.transpose()).inverse();
  Eigen::Matrix3d F = Skew(epipole) * to * pinv;
  const double norm = F.norm();
  if (!(norm > 0) || !F.allFinite()) return Eigen::Matrix3d::Zero();
  return F / norm;
}

std::optional<Eigen::Vector3d> EpipolarLine(const Eigen::Matrix3d& F,
                                            const Eigen::Vector2d& pixel) {
  const Eigen::Vector3d l = F * pixel.homogeneous();
  const double n = l.head<2>().norm();
  if (!(n > 1e-15 * (1.0 + std::abs(l.z())))) return std::nullopt;
  return l / n;
}

double LineDistance(const Eigen::Vector3d& line, const Eigen::Vector2d& pixel) {
  return line.dot(pixel.homogeneous());
}

std::optional<Eigen::Vector2d> Epipole(const Matrix34& from, const Matrix34& to) {
  const Eigen::Vector3d c = ProjectiveCamera(from, {}).Center();
  if (!c.allFinite()) return std::nullopt;
  return ProjectiveCamera(to, {}).Project(c);
}

Result<EpipolarSegment> ComputeEpipolarSegment(const ProjectiveCamera& from,
                                               const ProjectiveCamera& to,
                                               const Eigen::Vector2d& pixel, double depth_min,
                                               double depth_max) {
  if (!std::isfinite(depth_min) || !std::isfinite(depth_max) || !pixel.allFinite()) {
    return ErrorMessage{"depth window and pixel must be finite"};
  }
  if (!(depth_min > 0) || !(depth_max >= depth_min)) {
    return ErrorMessage{"depth window must satisfy 0 < depth_min <= depth_max"};
  }
  const auto near_world = PointAtDepth(from, pixel, depth_min);
  const auto far_world = PointAtDepth(from, pixel, depth_max);
  if (!near_world || !far_world) {
    return ErrorMessage{"the pixel's ray is parallel to the camera's focal plane"};
  }
  // Depth along a line is affine in the line parameter, so checking both ends covers the
  // whole window.
  if (!(to.Depth(*near_world) > 0) || !(to.Depth(*far_world) > 0)) {
    return ErrorMessage{"part of the depth window lies behind the other camera"};
  }
  const auto near = to.Project(*near_world);
  const auto far = to.Project(*far_world);
  if (!near || !far) {
    return ErrorMessage{"the depth window projects to infinity in the other camera"};
  }
  return EpipolarSegment{*near, *far, *near_world, *far_world};
}

}  // namespace igms::geometry
