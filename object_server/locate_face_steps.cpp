// A found block's silhouette edges beside a thin face (locate_steps.h: BoxFaceShifts,
// RefineBoxForFaces): blurred together with the face's other edge, the outer edge's gradient
// peak moves off the true outline.
#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "object_server/locate_steps.h"
#include "object_server/profile_step.h"
#include "object_server/silhouette_fit_steps.h"
#include "object_server/solid_models.h"

namespace igms::object {
namespace {

constexpr double kStep = 0.25;       // profile samples, pixels
constexpr double kOutside = 4.0;     // profile beyond the edge, pixels
constexpr double kReach = 1.5;       // where the step is looked for about the model's edge
constexpr double kMinStep = 8.0;     // grey levels: an outer step any weaker is not used
constexpr double kMaxMisfit = 0.05;  // the model's RMS misfit, as a share of the outer step
// A face narrower than this (pixels) is seen edge on: no face to model.
constexpr double kMinFacePx = 1.0;

double Phi(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// A profile across a silhouette edge, outward, from `inside` px within to kOutside px beyond
// the model's edge line, averaged along the edge; with where the fit's edge search finds the
// edge on the same lines.
struct FaceProfile {
  double width = 0, inside = 0;
  std::vector<double> grey;
  double peak = 0;
};

// The profile's step: a face `width` px wide between the next face's shade and the
// background's, through a Gaussian blur of sigma px: grey(d) = g + (f - g) Phi((d - e + w) /
// sigma) + (b - f) Phi((d - e) / sigma), linear in g, f - g and b - f. The best e within
// +-kReach, and whether the step is clear.
struct FaceStep {
  double at = 0, rss = std::numeric_limits<double>::infinity();
  bool clear = false;
};
FaceStep FitFaceStep(const FaceProfile& p, double sigma) {
  constexpr double kFine = 0.025;
  const ProfileStepFit<3> fit =
      FitProfileStep<3>(p.grey, -p.inside, kStep, kReach, 0.1, kFine, [&](double d, double e) {
        return Eigen::Vector3d(1.0, Phi((d - e + p.width) / sigma), Phi((d - e) / sigma));
      });
  FaceStep best;
  best.at = fit.at;
  best.rss = fit.rss;
  const double outer = std::abs(fit.coef[2]);
  const double rms = std::sqrt(std::max(0.0, best.rss) / static_cast<double>(p.grey.size()));
  best.clear = std::abs(best.at) < kReach - kFine && outer >= kMinStep && rms <= kMaxMisfit * outer;
  return best;
}

// The box's visible face beside the silhouette edge from corner a to corner b (they differ in
// one bit, the edge's axis): of the two faces through that edge, the one the camera sees. The
// bit that takes a corner of the edge to the face's opposite edge; -1 when neither is seen.
int FaceAcross(const Eigen::VectorXd& x, const Eigen::Vector3d& centre, int a, int b) {
  const int edge = a ^ b;
  const Eigen::Matrix3d R = BoxRotation(x[6]);
  const Eigen::Vector3d local = R.transpose() * (centre - x.head<3>());
  const Eigen::Vector3d h = 0.5 * x.segment<3>(3).cwiseAbs();
  for (int k = 0; k < 3; ++k) {  // the face where coordinate k is a's
    if ((edge >> k) & 1) continue;
    const bool plus = (a >> k) & 1;
    if ((plus ? local[k] - h[k] : -h[k] - local[k]) > 0) return 7 & ~edge & ~(1 << k);
  }
  return -1;
}

}  // namespace

std::vector<double> BoxFaceShifts(const cv::Mat& image, const geometry::ProjectiveCamera& camera,
                                  const Gradients& gradients, const Eigen::VectorXd& x,
                                  const std::vector<std::vector<Eigen::Vector2d>>& hidden,
                                  double min_gradient, double max_face_px) {
  std::vector<double> shifts(8, 0.0);
  ViewOutline o;
  if (x.size() != 7 || image.empty() || !ProjectOutline(BoxOutline(x), camera, o)) return shifts;
  const int n = static_cast<int>(o.hull.size());
  for (int i = 0; i < n; ++i) {
    const int a = o.hull[i], b = o.hull[(i + 1) % n];
    if (std::popcount(static_cast<unsigned>(a ^ b)) != 1) continue;  // not one box edge
    const int bit = FaceAcross(x, camera.Center(), a, b);
    if (bit < 0) continue;
    const Eigen::Vector2d pa = o.px[a], pb = o.px[b];
    const double len = (pb - pa).norm();
    if (len < 8) continue;
    const Eigen::Vector2d dir = (pb - pa) / len, out(dir.y(), -dir.x());  // hull: CCW in u-v
    FaceProfile p;
    p.width = std::abs(out.dot(o.px[a ^ bit] - pa));
    if (p.width < kMinFacePx || p.width > max_face_px) continue;
    p.inside = std::ceil((p.width + 3.0) / kStep) * kStep;
    const int samples = static_cast<int>(std::lround((p.inside + kOutside) / kStep)) + 1;
    p.grey.assign(samples, 0.0);
    const int lines = std::clamp(static_cast<int>(0.6 * len), 6, 48);
    int used = 0, peaks = 0;
    double peak_sum = 0;
    for (int j = 0; j < lines; ++j) {
      const Eigen::Vector2d q = pa + (0.2 + 0.6 * (j + 0.5) / lines) * len * dir;
      if (!SeenInImage(image, hidden, q - p.inside * out) ||
          !SeenInImage(image, hidden, q + kOutside * out))
        continue;
      for (int k = 0; k < samples; ++k)
        p.grey[k] += GreyAt(image, q + (-p.inside + k * kStep) * out);
      ++used;
      double at;
      if (EdgeAlongNormal(gradients, q, out, 2.5, min_gradient, &at)) {
        peak_sum += at;
        ++peaks;
      }
    }
    if (used < 6 || peaks < 6) continue;
    for (double& g : p.grey) g /= used;
    p.peak = peak_sum / peaks;
    FaceStep best;
    for (const double sigma : {0.5, 0.7, 0.9, 1.1, 1.3}) {
      const FaceStep s = FitFaceStep(p, sigma);
      if (s.rss < best.rss) best = s;
    }
    if (best.clear) shifts[a] = best.at - p.peak;
  }
  return shifts;
}

void RefineBoxForFaces(const StereoPair& pair, const std::array<FitView, 2>& views,
                       const FitOptions& fit, const LocateOptions& opt, FitOutcome* f) {
  if (!(opt.max_face_shading_px > 0) || !f->ok || f->params.size() != 7) return;
  std::array<FitView, 2> shaded = views;
  bool any = false;
  for (int v = 0; v < 2; ++v) {
    shaded[v].segment_shift_px =
        BoxFaceShifts(v ? pair.right : pair.left, *views[v].camera, *views[v].gradients, f->params,
                      views[v].hidden, fit.min_gradient, opt.max_face_px);
    for (double& s : shaded[v].segment_shift_px) {
      s = std::clamp(s, -opt.max_face_shading_px, opt.max_face_shading_px);
      any = any || s != 0;
    }
  }
  if (!any) return;
  FitOptions last = fit;
  last.first_outer = std::max(0, fit.outer_iterations - 1);
  InnerEdgesFn inner;
  if (opt.box_inner_edges) inner = BoxInnerEdges;
  FitOutcome g;
  if (f->params[6] == 0.0) {  // an aligned block stays aligned, as FitBox fitted it
    const AlignedBox aligned = AlignedBoxModel(inner);
    g = FitSilhouette(aligned.outline, f->params.head<6>(), shaded, last, aligned.inner);
    if (g.ok) g.params = WithZeroYaw(g.params);
  } else {
    g = FitSilhouette(BoxOutline, f->params, shaded, last, inner);
  }
  if (!g.ok || !g.params.allFinite()) return;
  // A correction of a fraction of a pixel moves the block within its own noise; one that moves
  // a centre coordinate or a size by more than its sigma rests on what the fit barely holds
  // (a far block's depth), and is not taken.
  for (int k = 0; k < 6; ++k)
    if (std::abs(g.params[k] - f->params[k]) > std::sqrt(std::max(0.0, f->covariance(k, k))))
      return;
  spdlog::debug(
      "locate: box edges beside thin faces moved: size {:.3f} {:.3f} {:.3f} against "
      "{:.3f} {:.3f} {:.3f}",
      g.params[3], g.params[4], g.params[5], f->params[3], f->params[4], f->params[5]);
  f->params = g.params;
}

}  // namespace igms::object
