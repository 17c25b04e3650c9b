#include "common/calibration/dlt.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/base/result.h"

namespace igms::calibration {
namespace {

bool CheckInput(std::span<const Correspondence> points, std::string* error) {
  if (points.size() < 6) {
    return Fail(error,
                "DLT needs at least 6 correspondences, got " + std::to_string(points.size()));
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].world.allFinite() || !points[i].pixel.allFinite()) {
      return Fail(error, "correspondence " + std::to_string(i + 1) + " is not finite");
    }
    mean += points[i].world;
  }
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
  for (const auto& p : points) spread += (p.world - mean) * (p.world - mean).transpose();
  const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::Matrix3d>(spread).singularValues();
  if (!(sv[0] > 0) || std::sqrt(sv[2] / sv[0]) < 1e-6) {
    return Fail(error, "world points are coplanar (or collinear): a plane does not determine P");
  }
  return true;
}

Result<geometry::Matrix34> SolveThesis(std::span<const Correspondence> points) {
  const auto n = static_cast<Eigen::Index>(points.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 11);
  Eigen::VectorXd b(2 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d& X = points[i].world;
    const double U = points[i].pixel.x(), V = points[i].pixel.y();
    A.block<1, 3>(2 * i, 0) = X.transpose();
    A(2 * i, 3) = 1;
    A.block<1, 3>(2 * i, 8) = -U * X.transpose();
    A.block<1, 3>(2 * i + 1, 4) = X.transpose();
    A(2 * i + 1, 7) = 1;
    A.block<1, 3>(2 * i + 1, 8) = -V * X.transpose();
    b[2 * i] = U;
    b[2 * i + 1] = V;
  }
  // The normal equations of the thesis, solved through QR for accuracy (same minimiser).
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < 11) {
    return ErrorMessage{"the linear system is rank deficient (degenerate point configuration)"};
  }
  const Eigen::VectorXd c = qr.solve(b);
  geometry::Matrix34 P;
  P << c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], c[9], c[10], 1.0;
  return P;
}

// Similarity moving the centroid to the origin with mean distance `target`.
template <int D>
Eigen::Matrix<double, D + 1, D + 1> Normalizer(const std::vector<Eigen::Matrix<double, D, 1>>& x,
                                               double target) {
  Eigen::Matrix<double, D, 1> mean = Eigen::Matrix<double, D, 1>::Zero();
  for (const auto& p : x) mean += p;
  mean /= x.size();
  double dist = 0;
  for (const auto& p : x) dist += (p - mean).norm();
  dist /= x.size();
  const double s = dist > 0 ? target / dist : 1.0;
  Eigen::Matrix<double, D + 1, D + 1> T = Eigen::Matrix<double, D + 1, D + 1>::Identity() * s;
  T(D, D) = 1;
  T.template topRightCorner<D, 1>() = -s * mean;
  return T;
}

Result<geometry::Matrix34> SolveNormalized(std::span<const Correspondence> points) {
  std::vector<Eigen::Vector3d> X;
  std::vector<Eigen::Vector2d> x;
  for (const auto& p : points) {
    X.push_back(p.world);
    x.push_back(p.pixel);
  }
  const Eigen::Matrix4d T = Normalizer<3>(X, std::sqrt(3.0));
  const Eigen::Matrix3d S = Normalizer<2>(x, std::sqrt(2.0));
  const auto n = static_cast<Eigen::Index>(points.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 12);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::RowVector4d Xn = (T * X[i].homogeneous()).transpose();
    const Eigen::Vector3d xn = S * x[i].homogeneous();
    A.block<1, 4>(2 * i, 0) = Xn;
    A.block<1, 4>(2 * i, 8) = -xn.x() * Xn;
    A.block<1, 4>(2 * i + 1, 4) = Xn;
    A.block<1, 4>(2 * i + 1, 8) = -xn.y() * Xn;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::VectorXd& sv = svd.singularValues();
  // One null direction is the answer; a second (near-)null one means the points do not pin P.
  if (!(sv[10] > 1e-9 * sv[0])) {
    return ErrorMessage{"the linear system is rank deficient (degenerate point configuration)"};
  }
  const Eigen::VectorXd p = svd.matrixV().col(11);
  geometry::Matrix34 Pn;
  Pn << p.segment<4>(0).transpose(), p.segment<4>(4).transpose(), p.segment<4>(8).transpose();
  geometry::Matrix34 P = S.inverse() * Pn * T;
  return geometry::Matrix34(P / P.norm());
}

}  // namespace

const char* ToString(DltMethod method) {
  return method == DltMethod::kThesis ? "thesis" : "normalized";
}

std::vector<double> ReprojectionResiduals(const geometry::Matrix34& P,
                                          std::span<const Correspondence> points) {
  const geometry::ProjectiveCamera camera(P, {});
  std::vector<double> r;
  r.reserve(points.size());
  for (const auto& p : points) {
    const auto px = camera.Project(p.world);
    r.push_back(px ? (*px - p.pixel).norm() : std::numeric_limits<double>::infinity());
  }
  return r;
}

Result<DltResult> CalibrateDlt(std::span<const Correspondence> points, DltMethod method) {
  if (std::string why; !CheckInput(points, &why)) return ErrorMessage{why};
  const auto P = method == DltMethod::kThesis ? SolveThesis(points) : SolveNormalized(points);
  if (!P.ok()) return ErrorMessage{P.error()};
  if (!P->allFinite()) {
    return ErrorMessage{"the solution is not finite"};
  }
  DltResult result;
  result.P = *P;
  result.residuals = ReprojectionResiduals(*P, points);
  double sum = 0;
  for (double r : result.residuals) {
    sum += r * r;
    result.max = std::max(result.max, r);
  }
  result.rms = std::sqrt(sum / static_cast<double>(result.residuals.size()));
  return result;
}

Result<std::vector<Correspondence>> ParseCorrespondences(const std::string& text) {
  std::vector<Correspondence> out;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    for (char& ch : line) {
      if (ch == ',' || ch == ';' || ch == '\t' || ch == '\r') ch = ' ';
    }
    std::istringstream fields(line);
    std::vector<double> values;
    std::string token;
    while (fields >> token) {
      char* end = nullptr;
      const double v = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0' || !std::isfinite(v)) {
        return ErrorMessage{"line " + std::to_string(number) + ": '" + token +
                            "' is not a finite number"};
      }
      values.push_back(v);
    }
    if (values.empty()) continue;
    if (values.size() != 5) {
      return ErrorMessage{"line " + std::to_string(number) +
                          ": expected 5 numbers (x y z u v), got " + std::to_string(values.size())};
    }
    out.push_back({{values[0], values[1], values[2]}, {values[3], values[4]}});
  }
  return out;
}

}  // namespace igms::calibration
