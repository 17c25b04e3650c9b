#include "common/calibration/platform_calibration.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/base/result.h"

namespace igms::calibration {
namespace {

using geometry::PlatformModel;

// The free parameters as a vector, applied on top of the initial model.
class Parameterization {
 public:
  Parameterization(const PlatformModel& initial, bool scales)
      : initial_(initial), scales_(scales) {}

  int size() const {
    const int n = static_cast<int>(initial_.joints.size());
    return 6 + 2 + 4 * (n - 2) + (scales_ ? n : 0);
  }

  PlatformModel Apply(const Eigen::VectorXd& x) const {
    PlatformModel m = initial_;
    const Eigen::Vector3d w = x.segment<3>(0);
    const double angle = w.norm();
    const Eigen::Matrix3d dR = angle > 0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix()
                                         : Eigen::Matrix3d::Identity();
    m.world_from_base.linear() = dR * initial_.world_from_base.linear();
    m.world_from_base.translation() = initial_.world_from_base.translation() + x.segment<3>(3);
    int k = 6;
    const int n = static_cast<int>(m.joints.size());
    m.joints[0].a += x[k++];
    m.joints[0].alpha += x[k++];
    for (int j = 1; j + 1 < n; ++j) {
      m.joints[j].theta_offset += x[k++];
      m.joints[j].d += x[k++];
      m.joints[j].a += x[k++];
      m.joints[j].alpha += x[k++];
    }
    if (scales_) {
      for (int j = 0; j < n; ++j) m.joints[j].radians_per_tick *= 1.0 + x[k++];
    }
    return m;
  }

 private:
  PlatformModel initial_;
  bool scales_;
};

Eigen::VectorXd Residuals(const geometry::Matrix34 P0[2], const PlatformModel& model,
                          std::span<const PlatformObservation> obs) {
  Eigen::VectorXd r(2 * obs.size());
  for (size_t i = 0; i < obs.size(); ++i) {
    const auto q = geometry::AnglesFromTicks(model, obs[i].ticks);
    const geometry::Matrix34 P = geometry::CameraAtPose(P0[obs[i].camera], model, q);
    const Eigen::Vector3d h = P * obs[i].world.homogeneous();
    r.segment<2>(2 * static_cast<Eigen::Index>(i)) = h.head<2>() / h.z() - obs[i].pixel;
  }
  return r;
}

// r holds an x and a y residual per point.
double Rms(const Eigen::VectorXd& r) {
  return std::sqrt(r.squaredNorm() / (static_cast<double>(r.size()) / 2));
}

}  // namespace

bool PlatformCalibrationOptions::Check(std::string* error) const {
  if (max_iterations < 1) return Fail(error, "max_iterations must be >= 1");
  return true;
}

std::vector<double> PlatformResiduals(const geometry::Matrix34& left_P0,
                                      const geometry::Matrix34& right_P0,
                                      const PlatformModel& model,
                                      std::span<const PlatformObservation> observations) {
  const geometry::Matrix34 P0[2] = {left_P0, right_P0};
  const Eigen::VectorXd r = Residuals(P0, model, observations);
  std::vector<double> out(observations.size());
  for (size_t i = 0; i < out.size(); ++i) {
    out[i] = r.segment<2>(2 * static_cast<Eigen::Index>(i)).norm();
  }
  return out;
}

Result<PlatformCalibrationResult> CalibratePlatform(
    const geometry::Matrix34& left_P0, const geometry::Matrix34& right_P0,
    const PlatformModel& initial, std::span<const PlatformObservation> observations,
    const PlatformCalibrationOptions& options, const PlatformProgress& progress) {
  std::string why;
  if (!options.Check(&why)) return ErrorMessage{why};
  if (!initial.Check(&why)) {
    return ErrorMessage{"initial platform model: " + why};
  }
  if (initial.joints.size() < 2) {
    return ErrorMessage{"platform calibration needs at least two joints"};
  }
  if (!left_P0.allFinite() || !right_P0.allFinite()) {
    return ErrorMessage{"camera matrices must be finite"};
  }
  for (size_t i = 0; i < observations.size(); ++i) {
    const auto& o = observations[i];
    const std::string where = "observation " + std::to_string(i + 1) + ": ";
    if (o.camera != 0 && o.camera != 1) {
      return ErrorMessage{where + "camera must be 0 (left) or 1 (right)"};
    }
    if (o.ticks.size() != initial.joints.size()) {
      return ErrorMessage{where + "expected " + std::to_string(initial.joints.size()) +
                          " joint values"};
    }
    bool finite = o.world.allFinite() && o.pixel.allFinite();
    for (double t : o.ticks) finite = finite && std::isfinite(t);
    if (!finite) {
      return ErrorMessage{where + "not finite"};
    }
  }
  const Parameterization param(initial, options.estimate_scales);
  const int np = param.size();
  if (static_cast<int>(2 * observations.size()) < np) {
    return ErrorMessage{"need at least " + std::to_string((np + 1) / 2) + " observations for " +
                        std::to_string(np) + " parameters, got " +
                        std::to_string(observations.size())};
  }
  const geometry::Matrix34 P0[2] = {left_P0, right_P0};
  auto residuals = [&](const Eigen::VectorXd& x) {
    return Residuals(P0, param.Apply(x), observations);
  };

  Eigen::VectorXd x = Eigen::VectorXd::Zero(np);
  Eigen::VectorXd r = residuals(x);
  PlatformCalibrationResult result;
  result.parameters = np;
  result.initial_rms = Rms(r);
  double cost = r.squaredNorm();
  double mu = 1e-3;
  constexpr double kStep = 1e-7;
  for (int it = 0; it < options.max_iterations; ++it) {
    result.iterations = it + 1;
    Eigen::MatrixXd J(r.size(), np);
    for (int k = 0; k < np; ++k) {
      Eigen::VectorXd a = x, b = x;
      a[k] += kStep;
      b[k] -= kStep;
      J.col(k) = (residuals(a) - residuals(b)) / (2 * kStep);
    }
    const Eigen::MatrixXd JtJ = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    const Eigen::VectorXd diag = JtJ.diagonal().cwiseMax(1e-12 * JtJ.diagonal().maxCoeff());
    if (!(JtJ.diagonal().maxCoeff() > 0)) {
      return ErrorMessage{"the observations do not constrain the platform (zero Jacobian)"};
    }
    bool improved = false;
    double new_cost = cost;
    for (int tries = 0; tries < 20 && !improved; ++tries) {
      Eigen::MatrixXd A = JtJ;
      A.diagonal() += mu * diag;
      const Eigen::VectorXd dx = A.ldlt().solve(-g);
      if (!dx.allFinite()) {
        mu *= 10;
        continue;
      }
      const Eigen::VectorXd r_new = residuals(x + dx);
      new_cost = r_new.squaredNorm();
      if (std::isfinite(new_cost) && new_cost < cost) {
        x += dx;
        r = r_new;
        improved = true;
        mu = std::max(mu / 3, 1e-12);
      } else {
        mu *= 4;
      }
    }
    if (progress) progress(it + 1, Rms(r));
    if (!improved) break;
    const double change = cost - new_cost;
    cost = new_cost;
    if (change < 1e-12 * cost || cost == 0) break;
  }
  // A singular normal matrix at the optimum means a direction the data does not see.
  {
    Eigen::MatrixXd J(r.size(), np);
    for (int k = 0; k < np; ++k) {
      Eigen::VectorXd a = x, b = x;
      a[k] += kStep;
      b[k] -= kStep;
      J.col(k) = (residuals(a) - residuals(b)) / (2 * kStep);
    }
    const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(J).singularValues();
    if (!(sv[np - 1] > 1e-9 * sv[0])) {
      return ErrorMessage{
          "the observations do not determine the platform (vary every joint, use several "
          "poses)"};
    }
  }
  result.model = param.Apply(x);
  result.rms = Rms(r);
  result.residuals.resize(observations.size());
  for (size_t i = 0; i < observations.size(); ++i) {
    result.residuals[i] = r.segment<2>(2 * static_cast<Eigen::Index>(i)).norm();
    result.max = std::max(result.max, result.residuals[i]);
  }
  return result;
}

Result<std::vector<PlatformObservation>> ParsePlatformObservations(const std::string& text,
                                                                   int joints) {
  std::vector<PlatformObservation> out;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    for (char& ch : line) {
      if (ch == ',' || ch == '\t' || ch == '\r') ch = ' ';
    }
    std::istringstream fields(line);
    std::string camera;
    if (!(fields >> camera)) continue;
    const std::string where = "line " + std::to_string(number) + ": ";
    PlatformObservation o;
    if (camera == "left" || camera == "0") {
      o.camera = 0;
    } else if (camera == "right" || camera == "1") {
      o.camera = 1;
    } else {
      return ErrorMessage{
          (where + "camera must be left, right, 0 or 1, got '").append(camera).append("'")};
    }
    std::vector<double> v;
    std::string token;
    while (fields >> token) {
      char* end = nullptr;
      const double value = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0' || !std::isfinite(value)) {
        return ErrorMessage{(where + "'").append(token).append("' is not a finite number")};
      }
      v.push_back(value);
    }
    if (static_cast<int>(v.size()) != joints + 5) {
      return ErrorMessage{where + "expected camera, " + std::to_string(joints) +
                          " joint values, x y z u v (" + std::to_string(joints + 5) +
                          " numbers), got " + std::to_string(v.size())};
    }
    o.ticks.assign(v.begin(), v.begin() + joints);
    o.world = Eigen::Vector3d(v[joints], v[joints + 1], v[joints + 2]);
    o.pixel = Eigen::Vector2d(v[joints + 3], v[joints + 4]);
    out.push_back(o);
  }
  return out;
}

}  // namespace igms::calibration
