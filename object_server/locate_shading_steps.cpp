// Whether a fitted pipe's side shades as a pipe's does (locate_steps.h: MeasureSideShading,
// ClassifySide): round across, where a block's faces shade flat and meet in a crease.
#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "object_server/locate_steps.h"

namespace igms::object {
namespace {

// The side's mean grey level across it: bins evenly spread in the sine of the angle round the
// axis (so evenly in the image), each over the middle 60% of the length.
struct Profile {
  std::vector<double> angle, sum, mean;
  std::vector<int> count;
};

// Profile of the side; empty when too narrow or short to tell, or a bin has under 3 samples.
Profile SampleProfile(const cv::Mat& image, const geometry::ProjectiveCamera& camera,
                      const Eigen::VectorXd& params,
                      const std::vector<std::vector<Eigen::Vector2d>>& hidden) {
  const Eigen::Vector3d p0 = params.segment<3>(0), p1 = params.segment<3>(3);
  const double r = std::abs(params[6]);
  Eigen::Vector3d axis = p1 - p0;
  const double len = axis.norm();
  if (len < 1e-9 || r < 1e-9 || image.empty()) return {};
  axis /= len;
  // w: the side's normal facing the camera; u: across the view.
  const Eigen::Vector3d mid = 0.5 * (p0 + p1);
  Eigen::Vector3d w = camera.Center() - mid;
  w -= w.dot(axis) * axis;
  if (w.norm() < 1e-9) return {};  // looking down the axis: no side seen
  w.normalize();
  const Eigen::Vector3d u = axis.cross(w);
  const auto qm = camera.Project(mid), qu = camera.Project(mid + r * u);
  const auto q0 = camera.Project(p0), q1 = camera.Project(p1);
  if (!qm || !qu || !q0 || !q1) return {};
  const double r_px = (*qu - *qm).norm(), len_px = (*q1 - *q0).norm();
  // Clear of the limbs by 2 px (the blur mixes the background in there); a bin a pixel wide.
  const double s_max = 1.0 - 2.0 / std::max(r_px, 1e-9);
  const int bins = std::min(16, static_cast<int>(2 * r_px * s_max));
  if (bins < 8 || len_px < 6) return {};
  const int steps = std::max(4, static_cast<int>(0.7 * len_px));
  Profile p;
  p.angle.resize(bins);
  p.sum.assign(bins, 0);
  p.mean.resize(bins);
  p.count.assign(bins, 0);
  for (int k = 0; k < bins; ++k) {
    p.angle[k] = std::asin(-s_max + 2 * s_max * (k + 0.5) / bins);
    const Eigen::Vector3d rim = r * (std::cos(p.angle[k]) * w + std::sin(p.angle[k]) * u);
    for (int j = 0; j < steps; ++j) {
      const double t = 0.2 + 0.6 * (j + 0.5) / steps;
      const auto q = camera.Project(p0 + t * len * axis + rim);
      if (!q || q->x() < 0 || q->y() < 0 || q->x() > image.cols - 1.001 ||
          q->y() > image.rows - 1.001 || InsideAny(hidden, *q))
        continue;
      p.sum[k] += GreyAt(image, *q);
      ++p.count[k];
    }
    if (p.count[k] < 3) return {};
    p.mean[k] = p.sum[k] / p.count[k];
  }
  return p;
}

}  // namespace

SideShading MeasureSideShading(const cv::Mat& image, const geometry::ProjectiveCamera& camera,
                               const Eigen::VectorXd& params,
                               const std::vector<std::vector<Eigen::Vector2d>>& hidden) {
  SideShading out;
  const Profile p = SampleProfile(image, camera, params, hidden);
  const int bins = static_cast<int>(p.mean.size());
  if (bins == 0) return out;
  // Residuals weighted by the bins' sample counts: each bin's mean is as good as its samples.
  double total = 0, samples = 0;
  for (int k = 0; k < bins; ++k) {
    total += p.sum[k];
    samples += p.count[k];
  }
  for (int k = 0; k < bins; ++k)
    out.flat_rss += p.count[k] * std::pow(p.mean[k] - total / samples, 2);
  // Round: a constant and the first two harmonics of the angle (Lambertian lights, clipped
  // where the side turns away from one).
  Eigen::MatrixXd A(bins, 5);
  Eigen::VectorXd b(bins);
  for (int k = 0; k < bins; ++k) {
    const double sw = std::sqrt(static_cast<double>(p.count[k])), a = p.angle[k];
    A.row(k) << sw, sw * std::cos(a), sw * std::sin(a), sw * std::cos(2 * a), sw * std::sin(2 * a);
    b[k] = sw * p.mean[k];
  }
  out.smooth_rss = (A * A.colPivHouseholderQr().solve(b) - b).squaredNorm();
  // Creased: two flat faces, each at least two bins wide.
  out.step_rss = std::numeric_limits<double>::infinity();
  double left_sum = 0, left_count = 0;
  for (int br = 1; br < bins; ++br) {
    left_sum += p.sum[br - 1];
    left_count += p.count[br - 1];
    if (br < 2 || br > bins - 2) continue;
    const double ml = left_sum / left_count, mr = (total - left_sum) / (samples - left_count);
    double rss = 0;
    for (int k = 0; k < bins; ++k) rss += p.count[k] * std::pow(p.mean[k] - (k < br ? ml : mr), 2);
    out.step_rss = std::min(out.step_rss, rss);
  }
  out.bins = bins;
  out.measured = true;
  return out;
}

SideShape ClassifySide(const StereoPair& pair, const Eigen::VectorXd& params,
                       const std::array<FitView, 2>& views, const LocateOptions& options) {
  int flat = 0, creased = 0, clearly_round = 0;
  for (int v = 0; v < 2; ++v) {
    const SideShading sh =
        MeasureSideShading(v ? pair.right : pair.left, v ? *pair.right_camera : *pair.left_camera,
                           params, views[v].hidden);
    if (!sh.measured) return SideShape::kUnmeasured;
    spdlog::debug(
        "locate: the side in the {} image shades {:.1f} times better round than flat, "
        "{:.1f} times better creased than round",
        v ? "right" : "left", sh.flat_rss / std::max(sh.smooth_rss, 1e-9),
        sh.smooth_rss / std::max(sh.step_rss, 1e-9));
    if (sh.smooth_rss > options.crease_gain * sh.step_rss)
      ++creased;
    else if (sh.flat_rss < options.flat_side_gain * sh.smooth_rss)
      ++flat;
    else if (sh.flat_rss >= options.round_side_gain * sh.smooth_rss)
      ++clearly_round;
  }
  if (creased == 2) return SideShape::kCreased;
  if (clearly_round == 2) return SideShape::kClearlyRound;
  return flat + creased == 2 ? SideShape::kFlat : SideShape::kRound;
}

}  // namespace igms::object
