#include "common/geometry/inverse_perspective.h"

#include <Eigen/Dense>
#include <cmath>

namespace igms::geometry {

std::pair<Eigen::Vector4d, Eigen::Vector4d> PixelPlanes(const Matrix34& P,
                                                        const Eigen::Vector2d& pixel) {
  const Eigen::Vector4d plane_u = (P.row(0) - pixel.x() * P.row(2)).transpose();
  const Eigen::Vector4d plane_v = (P.row(1) - pixel.y() * P.row(2)).transpose();
  return {plane_u, plane_v};
}

std::optional<Ray> LineFromPlanes(const Matrix34& P, const Eigen::Vector2d& pixel) {
  const auto [p1, p2] = PixelPlanes(P, pixel);
  const Eigen::Vector3d n1 = p1.head<3>(), n2 = p2.head<3>();
  Eigen::Vector3d d = n1.cross(n2);
  if (!(d.norm() > 1e-12 * n1.norm() * n2.norm())) return std::nullopt;
  // The point of the line nearest the origin solves n1.x = -d1, n2.x = -d2, d.x = 0.
  Eigen::Matrix3d A;
  A << n1.transpose(), n2.transpose(), d.transpose();
  const Eigen::Vector3d point = A.partialPivLu().solve(Eigen::Vector3d(-p1[3], -p2[3], 0.0));
  const ProjectiveCamera camera(P, {});
  if (d.dot(camera.ViewDirection()) < 0) d = -d;
  return Ray{point, d.normalized()};
}

std::optional<Eigen::Vector3d> PointAtHeight(const Matrix34& P, const Eigen::Vector2d& pixel,
                                             double z0) {
  const auto [p1, p2] = PixelPlanes(P, pixel);
  const double a1 = p1[0], b1 = p1[1], c1 = p1[2], d1 = p1[3];
  const double a2 = p2[0], b2 = p2[1], c2 = p2[2], d2 = p2[3];
  const double den = a1 * b2 - b1 * a2;
  if (!(std::abs(den) > 1e-12 * p1.head<3>().norm() * p2.head<3>().norm())) return std::nullopt;
  const double x0 = (b1 * (c2 * z0 + d2) - b2 * (c1 * z0 + d1)) / den;
  const double y0 = (a2 * (c1 * z0 + d1) - a1 * (c2 * z0 + d2)) / den;
  return Eigen::Vector3d(x0, y0, z0);
}

std::optional<Eigen::Vector3d> PointAtDepth(const ProjectiveCamera& camera,
                                            const Eigen::Vector2d& pixel, double depth) {
  const Ray ray = camera.PixelRay(pixel);
  const double cos_angle = ray.direction.dot(camera.ViewDirection());
  if (!(cos_angle > 1e-12)) return std::nullopt;
  return ray.At(depth / cos_angle);
}

}  // namespace igms::geometry
