#include "common/geometry/distortion.h"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

#include "common/base/result.h"

namespace igms::geometry {

bool ValidDistortionSize(size_t size) {
  return size == 0 || size == 4 || size == 5 || size == 8 || size == 12 || size == 14;
}

bool CheckDistortion(std::span<const double> coeffs, std::string* error) {
  if (!ValidDistortionSize(coeffs.size())) {
    return Fail(error, "expected 0, 4, 5, 8, 12 or 14 distortion coefficients, got " +
                           std::to_string(coeffs.size()));
  }
  for (double c : coeffs) {
    if (!std::isfinite(c)) return Fail(error, "distortion coefficient is not finite");
  }
  if (coeffs.size() == 14 && (coeffs[12] != 0.0 || coeffs[13] != 0.0)) {
    return Fail(error, "the tilted-sensor model (tau_x, tau_y non-zero) is not supported");
  }
  return true;
}

Eigen::Vector2d DistortNormalized(const Eigen::Vector2d& p, std::span<const double> c) {
  if (c.empty()) return p;
  if (!ValidDistortionSize(c.size())) throw std::invalid_argument("bad distortion size");
  auto k = [&](size_t i) { return i < c.size() ? c[i] : 0.0; };
  const double x = p.x(), y = p.y();
  const double r2 = x * x + y * y, r4 = r2 * r2, r6 = r4 * r2;
  const double radial =
      (1 + k(0) * r2 + k(1) * r4 + k(4) * r6) / (1 + k(5) * r2 + k(6) * r4 + k(7) * r6);
  const double xd = x * radial + 2 * k(2) * x * y + k(3) * (r2 + 2 * x * x) + k(8) * r2 + k(9) * r4;
  const double yd =
      y * radial + k(2) * (r2 + 2 * y * y) + 2 * k(3) * x * y + k(10) * r2 + k(11) * r4;
  return {xd, yd};
}

std::optional<Eigen::Vector2d> UndistortNormalized(const Eigen::Vector2d& distorted,
                                                   std::span<const double> coeffs) {
  if (coeffs.empty()) return distorted;
  if (!distorted.allFinite()) return std::nullopt;
  Eigen::Vector2d x = distorted;
  constexpr double kStep = 1e-7;
  for (int iteration = 0; iteration < 50; ++iteration) {
    const Eigen::Vector2d f = DistortNormalized(x, coeffs) - distorted;
    if (f.norm() < 1e-13) return x;
    Eigen::Matrix2d J;
    for (int i = 0; i < 2; ++i) {
      Eigen::Vector2d h = Eigen::Vector2d::Zero();
      h[i] = kStep;
      J.col(i) =
          (DistortNormalized(x + h, coeffs) - DistortNormalized(x - h, coeffs)) / (2 * kStep);
    }
    // A fold in the model (or its far wing) makes the Jacobian singular or flip orientation:
    // there is no unique inverse there.
    if (!(J.determinant() > 1e-9)) return std::nullopt;
    x -= J.inverse() * f;
    if (!x.allFinite()) return std::nullopt;
  }
  if ((DistortNormalized(x, coeffs) - distorted).norm() < 1e-10) return x;
  return std::nullopt;
}

}  // namespace igms::geometry
