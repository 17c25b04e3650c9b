#include "common/geometry/decomposition.h"

#include <Eigen/Dense>
#include <cmath>

namespace igms::geometry {
namespace {

bool CheckP(const Matrix34& P, std::string* error) {
  const Eigen::Matrix3d M = P.leftCols<3>();
  const double s = M.norm();
  if (!P.allFinite() || !(s > 0) || !(std::abs(M.determinant()) > 1e-12 * s * s * s)) {
    if (error) *error = "P must be finite with a non-singular left 3x3 block";
    return false;
  }
  return true;
}

Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& A) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

}  // namespace

Eigen::Matrix3d ThesisRotation(double theta, double phi, double psi) {
  const double ct = std::cos(theta), st = std::sin(theta);
  const double cf = std::cos(phi), sf = std::sin(phi);
  const double cp = std::cos(psi), sp = std::sin(psi);
  Eigen::Matrix3d Rt, Rf, Rp;
  Rt << ct, st, 0, -st, ct, 0, 0, 0, 1;
  Rf << 1, 0, 0, 0, cf, sf, 0, -sf, cf;
  Rp << cp, 0, -sp, 0, 1, 0, sp, 0, cp;
  return Rp * Rf * Rt;
}

Result<ThesisDecomposition> DecomposeThesis(const Matrix34& P) {
  std::string error;
  if (!CheckP(P, &error)) return ErrorMessage{error};
  const Eigen::Matrix3d M = P.leftCols<3>();
  const Eigen::Vector3d m1 = M.row(0), m2 = M.row(1), m3 = M.row(2);
  ThesisDecomposition d;
  // lambda's sign makes r2 the viewing direction (H&Z: sign(det M) m3), so the result does
  // not depend on P's scale or sign.
  d.lambda = (M.determinant() > 0 ? 1.0 : -1.0) * m3.norm();
  const Eigen::Vector3d r2 = m3 / d.lambda;
  d.u0 = m1.dot(m3) / m3.squaredNorm();
  d.v0 = m2.dot(m3) / m3.squaredNorm();
  const Eigen::Vector3d a = (m1 - d.u0 * m3) / d.lambda;  // ku r1
  const Eigen::Vector3d b = (m2 - d.v0 * m3) / d.lambda;  // kv r3
  // det M = lambda^3 (-ku kv) det R, so a proper R needs ku kv < 0: the thesis's choice is
  // ku < 0 < kv (u grows against x').
  d.ku = -a.norm();
  d.kv = b.norm();
  const Eigen::Vector3d r1 = a / d.ku, r3 = b / d.kv;
  d.skew = M_PI / 2 - std::acos(std::clamp(r1.dot(r3), -1.0, 1.0));
  Eigen::Matrix3d rows;
  rows << r1.transpose(), r2.transpose(), r3.transpose();
  d.R = NearestRotation(rows);
  const Eigen::Vector3d y = d.R.row(1);
  d.phi = std::asin(std::clamp(y.z(), -1.0, 1.0));
  d.theta = std::atan2(-y.x(), y.y());
  const Eigen::Matrix3d Rpsi = d.R * ThesisRotation(d.theta, d.phi, 0).transpose();
  d.psi = std::atan2(-Rpsi(0, 2), Rpsi(0, 0));
  d.printed_theta = std::remainder(d.theta - M_PI / 2, 2 * M_PI);
  d.printed_psi = std::remainder(M_PI - d.psi, 2 * M_PI);
  d.center = -M.partialPivLu().solve(P.col(3));
  return d;
}

Matrix34 ComposeThesis(const ThesisDecomposition& d) {
  const Eigen::Matrix3d R = ThesisRotation(d.theta, d.phi, d.psi);
  Eigen::Matrix<double, 3, 4> I;
  I << d.ku, d.u0, 0, 0, 0, d.v0, d.kv, 0, 0, 1, 0, 0;
  Eigen::Matrix4d W = Eigen::Matrix4d::Identity();
  W.topLeftCorner<3, 3>() = R;
  W.topRightCorner<3, 1>() = -R * d.center;
  Matrix34 C = I * W;
  if (std::abs(C(2, 3)) > 1e-9 * C.norm()) {
    C /= C(2, 3);
  } else {
    C *= d.lambda;
  }
  return C;
}

Result<RqDecomposition> DecomposeRq(const Matrix34& P_in) {
  std::string error;
  if (!CheckP(P_in, &error)) return ErrorMessage{error};
  Matrix34 P = P_in;
  if (P.leftCols<3>().determinant() < 0) P = -P;
  const Eigen::Matrix3d M = P.leftCols<3>();
  // RQ from QR: with J the row-reversing permutation, (J M)^T = Q' R' gives
  // M = (J R'^T J) (J Q'^T), upper triangular times orthogonal.
  Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
  J(0, 2) = J(1, 1) = J(2, 0) = 1;
  const Eigen::HouseholderQR<Eigen::Matrix3d> qr((J * M).transpose());
  const Eigen::Matrix3d Qp = qr.householderQ();
  const Eigen::Matrix3d Rp = qr.matrixQR().triangularView<Eigen::Upper>();
  Eigen::Matrix3d K = J * Rp.transpose() * J;
  Eigen::Matrix3d R = J * Qp.transpose();
  // Make K's diagonal positive: K D, D R with D = diag(+-1), D D = I.
  const Eigen::Vector3d signs = K.diagonal().unaryExpr([](double v) { return v < 0 ? -1.0 : 1.0; });
  K = K * signs.asDiagonal();
  R = signs.asDiagonal() * R;
  RqDecomposition d;
  d.K = K / K(2, 2);
  d.R = R;  // det M > 0 and K's diagonal positive make det R = +1
  d.center = -M.partialPivLu().solve(P.col(3));
  return d;
}

}  // namespace igms::geometry
