// Triangulation of a world point from its ideal (undistorted) pixels in two cameras
// (Cooke, section 3.7), three ways:
//
//  - kLinear:   the homogeneous linear (DLT) solution, Hartley & Zisserman 12.2: the SVD null
//               vector of the four equations u P3 - P1, v P3 - P2 of each camera, each row
//               scaled to unit norm. Fast, not optimal.
//  - kMidpoint: the midpoint of the shortest segment between the two pixel rays, the
//               thesis's "the rays intersect at the object point" made precise.
//  - kRefined:  the point minimising the sum of squared reprojection errors in both images
//               (the maximum-likelihood point under Gaussian pixel noise), by Gauss-Newton
//               from the linear solution.
//
// Every result carries its reprojection residuals and, when options.pixel_sigma > 0, the
// first-order 3x3 covariance of the point for independent isotropic pixel noise of that
// standard deviation on all four coordinates. For kRefined it is sigma^2 (J^T J)^-1 with J
// the 4x3 Jacobian of the two projections; for kLinear and kMidpoint it is the noise
// propagated through that method itself (central differences of the method with respect to
// the four pixel coordinates), so each method reports its own uncertainty.
//
// Units: world units for the point and covariance (units^2), pixels for residuals.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "common/base/result.h"
#include "common/geometry/camera.h"

namespace igms::geometry {

// d(u, v)/dX of the ideal projection by P at world point X: a world direction D moves the
// pixel by J D. Not finite on P's focal plane.
Eigen::Matrix<double, 2, 3> ProjectionJacobian(const Matrix34& P, const Eigen::Vector3d& X);

enum class TriangulationMethod { kLinear, kMidpoint, kRefined };

const char* ToString(TriangulationMethod method);

struct TriangulationOptions {
  // Standard deviation of the pixel noise, in pixels; 0 skips the covariance (left zero).
  double pixel_sigma = 0.5;
  // Gauss-Newton iterations of kRefined (it stops earlier when the step is below 1e-12
  // of the point's distance from the cameras).
  int max_iterations = 20;

  bool Check(std::string* error) const;
};

struct Triangulation {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  // Observed minus reprojected pixel in each camera.
  Eigen::Vector2d left_residual = Eigen::Vector2d::Zero();
  Eigen::Vector2d right_residual = Eigen::Vector2d::Zero();
  // Root mean square reprojection error over the two images:
  // sqrt((|left_residual|^2 + |right_residual|^2) / 2), pixels.
  double rms_error = 0.0;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  // Depth of the point in each camera (positive in front).
  double left_depth = 0.0;
  double right_depth = 0.0;
};

// Triangulates the world point seen at ideal pixel `left_pixel` in `left` and `right_pixel`
// in `right`. Fails (with the reason) when an input is not finite, the options are bad,
// the rays are parallel (no baseline, or a point at infinity), or the point lands behind
// either camera. Pixels far off the epipolar constraint still triangulate; their residuals
// say how far off they were.
Result<Triangulation> Triangulate(const Matrix34& left, const Matrix34& right,
                                  const Eigen::Vector2d& left_pixel,
                                  const Eigen::Vector2d& right_pixel, TriangulationMethod method,
                                  const TriangulationOptions& options = {});

}  // namespace igms::geometry
