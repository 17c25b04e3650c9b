// Decomposition of a projection matrix into the camera's parts (Cooke, section 3.3, after
// Ganapathy), and the same by RQ decomposition as a cross-check.
//
// The thesis's model (equations 3.13-3.24): C = lambda I W with
//     W = R_psi R_phi R_theta T(-centre)          (3.13-3.17; R_theta about z, R_phi about x,
//                                                 R_psi about y, each as printed there)
//     I = [ku  u0  0   0]                          (3.23, f folded into ku and kv)
//         [0   v0  kv  0]
//         [0   1   0   0]
// so the camera's y' axis (the second row r2 of R = R_psi R_phi R_theta) is the optical axis,
// x' maps to u and z' to v:  u = u0 + ku x'/y',  v = v0 + kv z'/y'.
// Writing M for C's left 3x3 block with rows m1, m2, m3:
//     r2 = m3 / lambda, lambda = sign(det M) |m3| (r2 is then the viewing direction)
//     u0 = m1.m3 / |m3|^2,  v0 = m2.m3 / |m3|^2
//     ku r1 = (m1 - u0 m3) / lambda,  kv r3 = (m2 - v0 m3) / lambda
// det M = lambda^3 (-ku kv) det R, so a proper rotation needs ku kv < 0; like the thesis we
// take ku < 0 < kv. For a camera with u right and v down in an upright world that puts
// psi near pi.
// A general 3x4 matrix has 11 degrees of freedom and this model 10: r1 and r3 need not come
// out orthogonal. `skew` reports that angle (pi/2 minus the angle between r1 and r3); the
// angles are taken from the nearest rotation (SVD) to the rows found.
// Angles: phi = asin(r2_z), theta = atan2(-r2_x, r2_y), psi from R (R_phi R_theta)^T.
// The thesis's printed angles lost their quadrants (they match inverse sines and cosines):
// for its matrices the printed theta is theta - pi/2 and the printed psi is pi - psi.
// `printed_theta` and `printed_psi` report those forms; docs/geometry.md shows the match.
//
// DecomposeRq is the textbook alternative: M = K R with K upper triangular, positive
// diagonal, K(2,2) = 1, R a rotation (camera_from_world, OpenCV's camera frame: x right,
// y down, z forward), centre from the null vector. P is negated first when det M < 0.
#pragma once

#include <Eigen/Core>
#include <string>

#include "common/base/result.h"
#include "common/geometry/camera.h"

namespace igms::geometry {

struct ThesisDecomposition {
  double ku = 0, kv = 0;  // pixels (focal length folded in); ku < 0 < kv for the thesis's C
  double u0 = 0, v0 = 0;  // pixels: the image centre
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // world units
  double theta = 0, phi = 0, psi = 0;                // radians, equations 3.14-3.16
  double printed_theta = 0;                          // theta - pi/2, the thesis's figure
  double printed_psi = 0;                            // pi - psi, the thesis's figure
  double skew = 0;                                   // radians, 0 for an exact model
  double lambda = 0;                                 // C = lambda I W
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();   // R_psi R_phi R_theta
};

// An error when P is not finite or its left 3x3 block is singular.
Result<ThesisDecomposition> DecomposeThesis(const Matrix34& P);

// lambda I W from the parts (skew ignored), scaled so that C(2,3) = 1 when C(2,3) is not
// near zero. Compose(Decompose(C)) == C for a skew-free C.
Matrix34 ComposeThesis(const ThesisDecomposition& d);

// R_psi R_phi R_theta of equations 3.14-3.16 (3x3 part).
Eigen::Matrix3d ThesisRotation(double theta, double phi, double psi);

struct RqDecomposition {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();  // upper triangular, K(2,2) = 1
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // camera_from_world rotation
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double fx() const { return K(0, 0); }
  double fy() const { return K(1, 1); }
  double cx() const { return K(0, 2); }
  double cy() const { return K(1, 2); }
  double skew() const { return K(0, 1); }
};

// An error when P is not finite or its left 3x3 block is singular.
Result<RqDecomposition> DecomposeRq(const Matrix34& P);

}  // namespace igms::geometry
