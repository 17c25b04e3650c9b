// Lens distortion in OpenCV's model (the `dist` coefficients of cv::calibrateCamera), applied
// to normalised image coordinates x = K^-1 * ideal pixel.
//
// Coefficient order, as OpenCV's: k1 k2 p1 p2 [k3 [k4 k5 k6 [s1 s2 s3 s4]]]. Accepted lengths
// are 0, 4, 5, 8 and 12; 14 (the tilted-sensor model) is accepted only when tau_x and tau_y
// are both zero. ValidDistortionSize() says whether a length is supported.
//
//   r2 = x^2 + y^2
//   radial = (1 + k1 r2 + k2 r2^2 + k3 r2^3) / (1 + k4 r2 + k5 r2^2 + k6 r2^3)
//   xd = x radial + 2 p1 x y + p2 (r2 + 2 x^2) + s1 r2 + s2 r2^2
//   yd = y radial + p1 (r2 + 2 y^2) + 2 p2 x y + s3 r2 + s4 r2^2
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>
#include <string>

namespace igms::geometry {

// True when `size` coefficients form a model this file implements (see above).
bool ValidDistortionSize(size_t size);

// Checks the length, finiteness and (for 14 coefficients) zero tilt. On failure returns false
// and, when `error` is given, says why.
bool CheckDistortion(std::span<const double> coeffs, std::string* error = nullptr);

// Normalised ideal coordinates to normalised distorted coordinates. Empty coefficients are the
// identity. The coefficients must pass CheckDistortion (a programmer error otherwise).
Eigen::Vector2d DistortNormalized(const Eigen::Vector2d& ideal, std::span<const double> coeffs);

// The inverse of DistortNormalized by Newton's method (with a numeric Jacobian), started at
// the distorted point. Converges to 1e-12 for any lens that is invertible over the region
// (every real lens, within its field of view). Returns nullopt when it does not converge or
// the model folds over (Jacobian singular), which happens far outside the image for strong
// barrel distortion.
std::optional<Eigen::Vector2d> UndistortNormalized(const Eigen::Vector2d& distorted,
                                                   std::span<const double> coeffs);

}  // namespace igms::geometry
