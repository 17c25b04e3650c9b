#include "object_server/silhouette_fit.h"

#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

namespace igms::object {
namespace {

double Cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

struct Measurement {
  int view;
  Eigen::Vector2d point;
};

// The outline of the model in one view, or empty when a point is behind the camera.
std::vector<Eigen::Vector2d> ProjectHull(const std::vector<Eigen::Vector3d>& pts,
                                         const geometry::ProjectiveCamera& cam) {
  std::vector<Eigen::Vector2d> px;
  px.reserve(pts.size());
  for (const auto& p : pts) {
    const Eigen::Vector3d x = cam.P() * p.homogeneous();
    if (cam.Depth(p) <= 0 || std::abs(x.z()) < 1e-12) return {};
    px.push_back(x.hnormalized());
  }
  return ConvexHull(std::move(px));
}

// Samples every pixel along the outline, away from corners sharper than 30 degrees.
void SampleOutline(const std::vector<Eigen::Vector2d>& hull, std::vector<Eigen::Vector2d>& points,
                   std::vector<Eigen::Vector2d>& normals) {
  const size_t n = hull.size();
  if (n < 3) return;
  // Corners: vertices where the outline turns by more than 30 degrees.
  std::vector<bool> corner(n);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d a = (hull[i] - hull[(i + n - 1) % n]).normalized();
    const Eigen::Vector2d b = (hull[(i + 1) % n] - hull[i]).normalized();
    corner[i] = a.dot(b) < std::cos(30.0 * M_PI / 180.0);
  }
  const double keep_off = 1.5, spacing = 1.0;
  double carry = 0;  // arc length into the next edge where the next sample falls
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d a = hull[i], b = hull[(i + 1) % n];
    const double len = (b - a).norm();
    if (len < 1e-9) continue;
    const Eigen::Vector2d dir = (b - a) / len;
    const Eigen::Vector2d normal(dir.y(), -dir.x());  // outward for a counter-clockwise hull
    double s = carry;
    for (; s < len; s += spacing) {
      if (corner[i] && s < keep_off) continue;
      if (corner[(i + 1) % n] && len - s < keep_off) continue;
      points.push_back(a + s * dir);
      normals.push_back(normal);
    }
    carry = s - len;
  }
}

}  // namespace

std::vector<Eigen::Vector2d> ConvexHull(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (p.size() < 3) return p;
  std::vector<Eigen::Vector2d> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && Cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && Cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

double SignedDistance(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& p) {
  const size_t n = hull.size();
  double max_line = -std::numeric_limits<double>::infinity();
  double min_seg = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d a = hull[i], b = hull[(i + 1) % n];
    const Eigen::Vector2d d = b - a;
    const double len2 = d.squaredNorm();
    if (len2 < 1e-18) continue;
    const Eigen::Vector2d normal = Eigen::Vector2d(d.y(), -d.x()) / std::sqrt(len2);
    max_line = std::max(max_line, normal.dot(p - a));
    const double t = std::clamp((p - a).dot(d) / len2, 0.0, 1.0);
    min_seg = std::min(min_seg, (a + t * d - p).norm());
  }
  return max_line <= 0 ? max_line : min_seg;
}

FitOutcome FitSilhouette(const OutlineFn& outline, const Eigen::VectorXd& initial,
                         const std::array<FitView, 2>& views, const FitOptions& options) {
  FitOutcome out;
  Eigen::VectorXd x = initial;
  const int np = static_cast<int>(x.size());
  const Eigen::VectorXd step =
      options.step.size() == np ? options.step : Eigen::VectorXd::Constant(np, 1e-4);

  auto hulls_of = [&](const Eigen::VectorXd& params, std::array<std::vector<Eigen::Vector2d>, 2>& hulls) {
    const auto pts = outline(params);
    for (int v = 0; v < 2; ++v) {
      hulls[v] = ProjectHull(pts, *views[v].camera);
      if (hulls[v].size() < 3) return false;
    }
    return true;
  };
  auto residuals = [&](const Eigen::VectorXd& params, const std::vector<Measurement>& ms,
                       Eigen::VectorXd& r) {
    std::array<std::vector<Eigen::Vector2d>, 2> hulls;
    if (!hulls_of(params, hulls)) return false;
    r.resize(ms.size());
    for (size_t i = 0; i < ms.size(); ++i) r[i] = SignedDistance(hulls[ms[i].view], ms[i].point);
    return true;
  };

  // Robust cost: Huber up to outlier_px, then flat, so moving away from edges never pays.
  double outlier = options.outlier_px;  // grows with the search range in early passes
  auto rho = [&](double res) {
    const double a = std::min(std::abs(res), outlier), k = options.huber_px;
    return a <= k ? 0.5 * a * a : k * (a - 0.5 * k);
  };
  auto cost_of = [&](const Eigen::VectorXd& res) {
    double c = 0;
    for (int i = 0; i < res.size(); ++i) c += rho(res[i]);
    return c;
  };
  std::vector<Measurement> ms;
  Eigen::VectorXd r, w;
  for (int outer = 0; outer < options.outer_iterations; ++outer) {
    const double range = outer == 0   ? options.search_px
                         : outer == 1 ? std::max(2.0, 0.6 * options.search_px)
                                      : std::max(1.5, 0.4 * options.search_px);
    outlier = std::max(options.outlier_px, range + 0.5);
    std::array<std::vector<Eigen::Vector2d>, 2> hulls;
    if (!hulls_of(x, hulls)) {
      out.error = "the model went behind a camera";
      return out;
    }
    ms.clear();
    for (int v = 0; v < 2; ++v) {
      std::vector<Eigen::Vector2d> pts, normals;
      SampleOutline(hulls[v], pts, normals);
      out.sampled[v] = static_cast<int>(pts.size());
      for (size_t i = 0; i < pts.size(); ++i) {
        double s;
        if (EdgeAlongNormal(*views[v].gradients, pts[i], normals[i], range, options.min_gradient, &s))
          ms.push_back({v, pts[i] + s * normals[i]});
      }
    }
    if (spdlog::should_log(spdlog::level::debug)) {
      std::string params;
      for (int i = 0; i < x.size(); ++i) params += fmt::format("{:.4f} ", x[i]);
      spdlog::debug("silhouette fit, pass {}: sampled {}/{}, {} edge measurements, x = {}", outer,
                    out.sampled[0], out.sampled[1], ms.size(), params);
    }
    if (static_cast<int>(ms.size()) < 2 * np) {
      out.error = "too few edge points along the model's outline";
      return out;
    }
    double lambda = 1e-3;
    for (int inner = 0; inner < options.inner_iterations; ++inner) {
      if (!residuals(x, ms, r)) break;
      w.resize(r.size());
      for (int i = 0; i < r.size(); ++i) {
        const double a = std::abs(r[i]);
        w[i] = a > outlier ? 0.0 : (a <= options.huber_px ? 1.0 : options.huber_px / a);
      }
      Eigen::MatrixXd J(r.size(), np);
      for (int k = 0; k < np; ++k) {
        Eigen::VectorXd xp = x, rp;
        xp[k] += step[k];
        if (!residuals(xp, ms, rp)) {
          out.error = "the model went behind a camera";
          return out;
        }
        J.col(k) = (rp - r) / step[k];
      }
      const Eigen::MatrixXd JtW = J.transpose() * w.asDiagonal();
      const Eigen::MatrixXd H = JtW * J;
      const Eigen::VectorXd g = JtW * r;
      const double cost = cost_of(r);
      bool improved = false;
      for (int tries = 0; tries < 8 && !improved; ++tries) {
        Eigen::MatrixXd A = H;
        // Directions no edge constrains (an end with no measurement yet) must not drift:
        // a small stiffness relative to the mean curvature holds them.
        A.diagonal() += lambda * H.diagonal() + Eigen::VectorXd::Constant(np, 1e-3 * H.diagonal().mean() + 1e-9);
        const Eigen::VectorXd dx = -A.ldlt().solve(g);
        Eigen::VectorXd rn;
        if (dx.allFinite() && residuals(x + dx, ms, rn) && cost_of(rn) < cost) {
          x += dx;
          lambda = std::max(1e-7, lambda * 0.3);
          improved = true;
        } else {
          lambda *= 10;
        }
      }
      if (!improved) break;
    }
  }
  // Final statistics and covariance on the last measurements.
  if (!residuals(x, ms, r)) {
    out.error = "the model went behind a camera";
    return out;
  }
  Eigen::MatrixXd J(r.size(), np);
  for (int k = 0; k < np; ++k) {
    Eigen::VectorXd xp = x, rp;
    xp[k] += step[k];
    residuals(xp, ms, rp);
    J.col(k) = (rp - r) / step[k];
  }
  std::array<double, 2> sum{0, 0};
  std::array<int, 2> count{0, 0};
  Eigen::VectorXd wk = Eigen::VectorXd::Zero(r.size());
  for (int i = 0; i < r.size(); ++i) {
    if (std::abs(r[i]) > options.outlier_px) continue;
    wk[i] = 1;
    sum[ms[i].view] += r[i] * r[i];
    ++count[ms[i].view];
  }
  for (int v = 0; v < 2; ++v) {
    out.used[v] = count[v];
    out.rms_px[v] = count[v] ? std::sqrt(sum[v] / count[v]) : 0;
  }
  const double dof = std::max(1, count[0] + count[1] - np);
  const double sigma2 = (sum[0] + sum[1]) / dof;
  const Eigen::MatrixXd H = J.transpose() * wk.asDiagonal() * J;
  out.covariance = sigma2 * H.completeOrthogonalDecomposition().pseudoInverse();
  out.params = x;
  out.ok = x.allFinite();
  if (!out.ok) out.error = "the fit diverged";
  return out;
}

}  // namespace igms::object
