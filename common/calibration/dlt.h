// Camera calibration from world/image correspondences by the direct linear transform
// (Cooke, section 3.2, equation 3.12, after Ballard and Brown).
//
// Two formulations:
//  - kThesis: C34 fixed to 1, the other eleven entries by linear least squares of the
//    thesis's equations 3.10-3.11 (its matrix 3.12, whose second row should read -V, not -U).
//    Fails when the world origin lies on or near the camera's focal plane (true C34 near 0).
//  - kNormalized: Hartley's normalised DLT (Hartley & Zisserman, algorithm 7.1): world
//    points and pixels translated to their centroids and scaled to mean distances sqrt(3)
//    and sqrt(2), the 2n x 12 homogeneous system solved by SVD, then denormalised. Minimises
//    algebraic error without any special entry; better conditioned.
// Both minimise an algebraic error; residuals are reported geometrically: the pixel
// distance between each observed pixel and the reprojected world point.
//
// Input is refused (an ErrorMessage saying why) when there are fewer than six correspondences,
// a value is not finite, the world points are coplanar or collinear (the smallest singular
// value of their centred spread under 1e-6 of the largest: a plane does not determine P), or
// the linear system is rank deficient.
#pragma once

#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/geometry/camera.h"

namespace igms::calibration {

struct Correspondence {
  Eigen::Vector3d world;
  Eigen::Vector2d pixel;
};

enum class DltMethod { kThesis, kNormalized };
const char* ToString(DltMethod method);

struct DltResult {
  geometry::Matrix34 P;           // kThesis: P(2,3) = 1; kNormalized: unit Frobenius norm
  std::vector<double> residuals;  // pixels, one per correspondence, in input order
  double rms = 0;                 // root mean square of residuals
  double max = 0;
};

Result<DltResult> CalibrateDlt(std::span<const Correspondence> points, DltMethod method);

// Residuals of any P against correspondences (pixel distance; infinity for a point on P's
// focal plane).
std::vector<double> ReprojectionResiduals(const geometry::Matrix34& P,
                                          std::span<const Correspondence> points);

// Reads "x y z u v" lines (whitespace or commas between numbers; '#' starts a comment;
// blank lines skipped). An ErrorMessage "line N: ..." on a malformed line.
Result<std::vector<Correspondence>> ParseCorrespondences(const std::string& text);

}  // namespace igms::calibration
