#include "common/geometry/triangulation.h"

#include <Eigen/Dense>
#include <Eigen/SVD>
#include <array>
#include <cmath>

#include "common/base/result.h"

namespace igms::geometry {

Eigen::Matrix<double, 2, 3> ProjectionJacobian(const Matrix34& P, const Eigen::Vector3d& X) {
  const Eigen::Vector3d h = P * X.homogeneous();
  Eigen::Matrix<double, 2, 3> J;
  J.row(0) = (P.block<1, 3>(0, 0) - h.x() / h.z() * P.block<1, 3>(2, 0)) / h.z();
  J.row(1) = (P.block<1, 3>(1, 0) - h.y() / h.z() * P.block<1, 3>(2, 0)) / h.z();
  return J;
}

namespace {

using Pixels = Eigen::Vector4d;  // left u, left v, right u, right v

std::optional<Eigen::Vector3d> Linear(const Matrix34& L, const Matrix34& R, const Pixels& x) {
  Eigen::Matrix4d A;
  A.row(0) = x[0] * L.row(2) - L.row(0);
  A.row(1) = x[1] * L.row(2) - L.row(1);
  A.row(2) = x[2] * R.row(2) - R.row(0);
  A.row(3) = x[3] * R.row(2) - R.row(1);
  for (int i = 0; i < 4; ++i) A.row(i).normalize();
  const Eigen::JacobiSVD<Eigen::Matrix4d> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d X = svd.matrixV().col(3);
  // A homogeneous coordinate near zero is a point at infinity: parallel rays.
  if (!(std::abs(X[3]) > 1e-12)) return std::nullopt;
  return X.hnormalized();
}

std::optional<Eigen::Vector3d> Midpoint(const Matrix34& L, const Matrix34& R, const Pixels& x) {
  const Ray a = ProjectiveCamera(L, {}).PixelRay(x.head<2>());
  const Ray b = ProjectiveCamera(R, {}).PixelRay(x.tail<2>());
  // Closest points a.origin + s a.dir, b.origin + t b.dir (unit directions).
  const Eigen::Vector3d w = a.origin - b.origin;
  const double c = a.direction.dot(b.direction);
  const double den = 1.0 - c * c;
  if (!(den > 1e-14)) return std::nullopt;
  const double d = a.direction.dot(w), e = b.direction.dot(w);
  const double s = (c * e - d) / den;
  const double t = (e - c * d) / den;
  return 0.5 * (a.At(s) + b.At(t));
}

Eigen::Vector4d Residuals(const Matrix34& L, const Matrix34& R, const Pixels& x,
                          const Eigen::Vector3d& X) {
  Eigen::Vector4d r;
  r.head<2>() = x.head<2>() - (L * X.homogeneous()).hnormalized();
  r.tail<2>() = x.tail<2>() - (R * X.homogeneous()).hnormalized();
  return r;
}

std::optional<Eigen::Vector3d> Refined(const Matrix34& L, const Matrix34& R, const Pixels& x,
                                       int max_iterations) {
  auto start = Linear(L, R, x);
  if (!start) return std::nullopt;
  Eigen::Vector3d X = *start;
  const double scale = 1.0 + (X - ProjectiveCamera(L, {}).Center()).norm();
  for (int i = 0; i < max_iterations; ++i) {
    Eigen::Matrix<double, 4, 3> J;
    J.topRows<2>() = ProjectionJacobian(L, X);
    J.bottomRows<2>() = ProjectionJacobian(R, X);
    const Eigen::Vector3d step =
        (J.transpose() * J).ldlt().solve(J.transpose() * Residuals(L, R, x, X));
    if (!step.allFinite()) return std::nullopt;
    X += step;
    if (step.norm() < 1e-12 * scale) break;
  }
  return X;
}

std::optional<Eigen::Vector3d> Solve(const Matrix34& L, const Matrix34& R, const Pixels& x,
                                     TriangulationMethod method, int max_iterations) {
  switch (method) {
    case TriangulationMethod::kLinear:
      return Linear(L, R, x);
    case TriangulationMethod::kMidpoint:
      return Midpoint(L, R, x);
    case TriangulationMethod::kRefined:
      return Refined(L, R, x, max_iterations);
  }
  return std::nullopt;
}

// Noise propagated through the method: cov = sigma^2 G G^T with G = dX/dpixels.
std::optional<Eigen::Matrix3d> PropagatedCovariance(const Matrix34& L, const Matrix34& R,
                                                    const Pixels& x, TriangulationMethod method,
                                                    const TriangulationOptions& options) {
  constexpr double kStep = 1e-3;  // pixels: small against noise, large against round-off
  Eigen::Matrix<double, 3, 4> G;
  for (int i = 0; i < 4; ++i) {
    Pixels plus = x, minus = x;
    plus[i] += kStep;
    minus[i] -= kStep;
    auto a = Solve(L, R, plus, method, options.max_iterations);
    auto b = Solve(L, R, minus, method, options.max_iterations);
    if (!a || !b) return std::nullopt;
    G.col(i) = (*a - *b) / (2 * kStep);
  }
  return options.pixel_sigma * options.pixel_sigma * G * G.transpose();
}

}  // namespace

const char* ToString(TriangulationMethod method) {
  switch (method) {
    case TriangulationMethod::kLinear:
      return "linear";
    case TriangulationMethod::kMidpoint:
      return "midpoint";
    case TriangulationMethod::kRefined:
      return "refined";
  }
  return "unknown";
}

bool TriangulationOptions::Check(std::string* error) const {
  if (!(pixel_sigma >= 0) || !std::isfinite(pixel_sigma)) {
    return Fail(error, "pixel_sigma must be finite and >= 0");
  }
  if (max_iterations < 1) return Fail(error, "max_iterations must be >= 1");
  return true;
}

Result<Triangulation> Triangulate(const Matrix34& left, const Matrix34& right,
                                  const Eigen::Vector2d& left_pixel,
                                  const Eigen::Vector2d& right_pixel, TriangulationMethod method,
                                  const TriangulationOptions& options) {
  if (std::string why; !options.Check(&why)) return ErrorMessage{why};
  if (!left.allFinite() || !right.allFinite() || !left_pixel.allFinite() ||
      !right_pixel.allFinite()) {
    return ErrorMessage{"triangulation input is not finite"};
  }
  const Pixels x(left_pixel.x(), left_pixel.y(), right_pixel.x(), right_pixel.y());
  auto point = Solve(left, right, x, method, options.max_iterations);
  if (!point || !point->allFinite()) {
    return ErrorMessage{"the two rays are parallel: no finite intersection"};
  }
  Triangulation t;
  t.point = *point;
  t.left_depth = ProjectiveCamera(left, {}).Depth(t.point);
  t.right_depth = ProjectiveCamera(right, {}).Depth(t.point);
  if (!(t.left_depth > 0) || !(t.right_depth > 0)) {
    return ErrorMessage{"the triangulated point lies behind a camera"};
  }
  const Eigen::Vector4d r = Residuals(left, right, x, t.point);
  t.left_residual = r.head<2>();
  t.right_residual = r.tail<2>();
  t.rms_error = std::sqrt(r.squaredNorm() / 2.0);
  if (options.pixel_sigma > 0) {
    if (method == TriangulationMethod::kRefined) {
      Eigen::Matrix<double, 4, 3> J;
      J.topRows<2>() = ProjectionJacobian(left, t.point);
      J.bottomRows<2>() = ProjectionJacobian(right, t.point);
      t.covariance = options.pixel_sigma * options.pixel_sigma * (J.transpose() * J).inverse();
    } else {
      auto cov = PropagatedCovariance(left, right, x, method, options);
      if (!cov) {
        return ErrorMessage{"covariance undefined: the rays are nearly parallel"};
      }
      t.covariance = *cov;
    }
  }
  return t;
}

}  // namespace igms::geometry
