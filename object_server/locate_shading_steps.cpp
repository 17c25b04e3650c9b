// Whether a fitted pipe's side shades as a pipe's does (locate_steps.h: MeasureSideShading,
// ClassifySide): round across, where a block's faces shade flat and meet in a crease.
#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "object_server/locate_steps.h"
#include "object_server/profile_step.h"
#include "object_server/solid_models.h"

namespace igms::object {
namespace {

// A limb whose profile steps by less than this (grey levels) has no clear edge to place.
constexpr double kMinLimbStep = 8.0;
// ... or whose profile the model leaves more than this share of its step unexplained (RMS): a
// shadow's edge or another object beside it, or a side too narrow for the model (about 5 px
// across: the easy scenes' pipes so refused would have come out 0.016-0.022 in too thick;
// those moved, within 0.015 of their step).
constexpr double kMaxLimbMisfit = 0.02;

// The side's mean grey level across it: bins evenly spread in the sine of the angle round the
// axis (so evenly in the image), each over the middle 60% of the length.
struct Profile {
  std::vector<double> angle, sum, mean;
  std::vector<int> count;
};

// A pipe's side as a camera sees it: w, the side's normal facing the camera; u, across the
// view; the side's half width and length in the image, and the image's direction of u.
struct SideFrame {
  bool ok = false;
  Eigen::Vector3d p0, axis, w, u;  // axis: unit
  double len = 0, r = 0, r_px = 0, len_px = 0;
  Eigen::Vector2d across;
};

SideFrame FrameOfSide(const geometry::ProjectiveCamera& camera, const Eigen::VectorXd& params) {
  SideFrame f;
  f.p0 = params.segment<3>(0);
  const Eigen::Vector3d p1 = params.segment<3>(3);
  f.r = std::abs(params[6]);
  f.axis = p1 - f.p0;
  f.len = f.axis.norm();
  if (f.len < 1e-9 || f.r < 1e-9) return f;
  f.axis /= f.len;
  const Eigen::Vector3d mid = 0.5 * (f.p0 + p1);
  f.w = camera.Center() - mid;
  f.w -= f.w.dot(f.axis) * f.axis;
  if (f.w.norm() < 1e-9) return f;  // looking down the axis: no side seen
  f.w.normalize();
  f.u = f.axis.cross(f.w);
  const auto qm = camera.Project(mid), qu = camera.Project(mid + f.r * f.u);
  const auto q0 = camera.Project(f.p0), q1 = camera.Project(p1);
  if (!qm || !qu || !q0 || !q1) return f;
  f.r_px = (*qu - *qm).norm();
  f.len_px = (*q1 - *q0).norm();
  if (f.r_px < 1e-9) return f;
  f.across = (*qu - *qm) / f.r_px;
  f.ok = true;
  return f;
}

// Profile of the side; empty when too narrow or short to tell, or a bin has under 3 samples.
Profile SampleProfile(const cv::Mat& image, const geometry::ProjectiveCamera& camera,
                      const Eigen::VectorXd& params,
                      const std::vector<std::vector<Eigen::Vector2d>>& hidden,
                      bool half_pixel_bins) {
  const SideFrame side = FrameOfSide(camera, params);
  if (!side.ok || image.empty()) return {};
  const Eigen::Vector3d &p0 = side.p0, &axis = side.axis, &w = side.w, &u = side.u;
  const double r = side.r, len = side.len, r_px = side.r_px, len_px = side.len_px;
  // Clear of the limbs by 2 px (the blur mixes the background in there); a bin a pixel wide,
  // or half a pixel where that leaves under 8 bins (half_pixel_bins).
  const double s_max = 1.0 - 2.0 / std::max(r_px, 1e-9);
  const double clear_px = 2 * r_px * s_max;
  int bins = std::min(16, static_cast<int>(clear_px));
  if (bins < 8 && half_pixel_bins) bins = static_cast<int>(2 * clear_px);  // under 16: clear_px < 8
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
      if (!q || !SeenInImage(image, hidden, *q)) continue;
      p.sum[k] += GreyAt(image, *q);
      ++p.count[k];
    }
    if (p.count[k] < 3) return {};
    p.mean[k] = p.sum[k] / p.count[k];
  }
  return p;
}

// A limb's grey-level profile across it, outward from the model's limb line, averaged along
// the middle 60% of the side: sub-pixel samples every kProfileStep pixels.
constexpr double kProfileStep = 0.25;

// The profile's model: a step from the side's shade to the background at e, the side shading
// as a Lambertian cylinder's under distant lights (a constant, and the cosine and sine of the
// angle round the axis, which the depth inside the limb fixes: sine 1 - depth / r_px), seen
// through the camera's blur (a Gaussian of sigma pixels). Its four terms at offset z = d - e,
// tabulated for one sigma and half width.
class LimbProfileModel {
 public:
  LimbProfileModel(double sigma, double r_px, double inside, double outside)
      : z0_(-inside - 1), n_(static_cast<int>((inside + outside + 2) / kGrid) + 1), table_(n_) {
    // Depth j inside the limb lies at (j + 0.5) grid steps; offset i adds i steps: the
    // Gaussian's weight depends on i + j alone, worked out once.
    const int depths = static_cast<int>(std::min(2 * r_px, inside + 4 * sigma) / kGrid);
    std::vector<double> weight(n_ + depths), cosine(depths), sine(depths);
    for (size_t m = 0; m < weight.size(); ++m) {
      const double v = (z0_ + (static_cast<double>(m) + 0.5) * kGrid) / sigma;
      weight[m] = std::exp(-0.5 * v * v) * kGrid / (sigma * std::sqrt(2 * M_PI));
    }
    for (int j = 0; j < depths; ++j) {
      sine[j] = 1 - (j + 0.5) * kGrid / r_px;
      cosine[j] = std::sqrt(std::max(0.0, 1 - sine[j] * sine[j]));
    }
    for (int i = 0; i < n_; ++i) {
      const double z = z0_ + i * kGrid;
      Eigen::Vector4d t(0.5 * std::erfc(-z / (sigma * std::sqrt(2.0))), 0, 0, 0);
      for (int j = 0; j < depths; ++j) {
        const double w = weight[i + j];
        t[1] += w;
        t[2] += w * cosine[j];
        t[3] += w * sine[j];
      }
      table_[i] = t;
    }
  }
  Eigen::Vector4d At(double z) const {
    const double x = std::clamp((z - z0_) / kGrid, 0.0, n_ - 1.001);
    const int i = static_cast<int>(x);
    return table_[i] + (x - i) * (table_[i + 1] - table_[i]);
  }

 private:
  static constexpr double kGrid = 0.1;
  double z0_;
  int n_;
  std::vector<Eigen::Vector4d> table_;
};

// The profile's step (offset from the model's limb line, outward positive) for one camera
// blur: the model above fitted over the step's place within +-kStepReach, its residual sum of
// squares, and whether the step is clear (over min_step grey levels and short of the reach).
constexpr double kStepReach = 2.0;
struct StepFit {
  double at = 0, rss = std::numeric_limits<double>::infinity();
  bool clear = false;
};
StepFit FitStep(const LimbProfile& limb, const LimbProfileModel& model, double min_step) {
  // Every 0.2 px over the reach, then every 0.05 px about the best.
  constexpr double kFine = 0.05;
  const ProfileStepFit<4> fit =
      FitProfileStep<4>(limb.grey, -limb.inside, kProfileStep, kStepReach, 0.2, kFine,
                        [&](double d, double e) { return model.At(d - e); });
  StepFit best;
  best.at = fit.at;
  best.rss = fit.rss;
  // The shade at the limb (cosine 0, sine 1) against the background, and the model's misfit.
  const double contrast = std::abs(fit.coef[1] + fit.coef[3] - fit.coef[0]);
  const double rms = std::sqrt(std::max(0.0, best.rss) / static_cast<double>(limb.grey.size()));
  best.clear = std::abs(best.at) < kStepReach - kFine && contrast >= min_step &&
               rms <= kMaxLimbMisfit * contrast;
  return best;
}

}  // namespace

bool SeenInImage(const cv::Mat& image, const std::vector<std::vector<Eigen::Vector2d>>& hidden,
                 const Eigen::Vector2d& q) {
  return q.x() >= 0 && q.y() >= 0 && q.x() <= image.cols - 1.001 && q.y() <= image.rows - 1.001 &&
         !InsideAny(hidden, q);
}

std::array<std::optional<LimbProfile>, 2> LimbProfiles(
    const cv::Mat& image, const geometry::ProjectiveCamera& camera, const Gradients& gradients,
    const Eigen::VectorXd& params, const std::vector<std::vector<Eigen::Vector2d>>& hidden,
    double min_gradient) {
  std::array<std::optional<LimbProfile>, 2> out;
  const SideFrame side = FrameOfSide(camera, params);
  if (!side.ok || image.empty() || side.len_px < 8) return out;
  // Inside up to the side's far half (the other limb's blur beyond), outside 4 px.
  LimbProfile limb;
  limb.r_px = side.r_px;
  limb.inside = std::floor(std::min(6.0, 2 * side.r_px - 2) / kProfileStep) * kProfileStep;
  limb.outside = 4.0;
  if (limb.inside < 1.5) return out;
  const int n = static_cast<int>(std::lround((limb.inside + limb.outside) / kProfileStep)) + 1;
  const int lines = std::clamp(static_cast<int>(0.6 * side.len_px), 8, 64);
  for (int s = 0; s < 2; ++s) {
    const double sign = s ? 1.0 : -1.0;
    const Eigen::Vector2d out_dir = sign * side.across;
    limb.grey.assign(n, 0.0);
    double peak_sum = 0;
    int used = 0, peaks = 0;
    for (int j = 0; j < lines; ++j) {
      const double t = 0.2 + 0.6 * (j + 0.5) / lines;
      const auto q = camera.Project(side.p0 + t * side.len * side.axis + sign * side.r * side.u);
      if (!q || !SeenInImage(image, hidden, *q - limb.inside * out_dir) ||
          !SeenInImage(image, hidden, *q + limb.outside * out_dir) ||
          !SeenInImage(image, hidden, *q))
        continue;
      for (int k = 0; k < n; ++k)
        limb.grey[k] += GreyAt(image, *q + (-limb.inside + k * kProfileStep) * out_dir);
      ++used;
      double at;  // where the fit's edge search finds the limb on this line
      if (EdgeAlongNormal(gradients, *q, out_dir, 2.5, min_gradient, &at)) {
        peak_sum += at;
        ++peaks;
      }
    }
    if (used < 6 || peaks < 6) continue;
    for (double& g : limb.grey) g /= used;
    limb.peak = peak_sum / peaks;
    out[s] = limb;
  }
  return out;
}

std::optional<double> LimbEdgeShift(const std::vector<LimbProfile>& limbs, double min_step) {
  if (limbs.empty()) return std::nullopt;
  double best_rss = std::numeric_limits<double>::infinity();
  std::vector<StepFit> best;
  for (const double sigma : {0.5, 0.7, 0.9, 1.1, 1.3}) {
    std::vector<StepFit> fits;
    double rss = 0;
    // Both limbs of a view share their model (their half width and extents).
    std::optional<LimbProfileModel> model;
    const LimbProfile* modelled = nullptr;
    for (const LimbProfile& limb : limbs) {
      if (!modelled || limb.r_px != modelled->r_px || limb.inside != modelled->inside) {
        model.emplace(sigma, limb.r_px, limb.inside + kStepReach, limb.outside + kStepReach);
        modelled = &limb;
      }
      fits.push_back(FitStep(limb, *model, min_step));
      rss += fits.back().rss;
    }
    if (rss < best_rss) {
      best_rss = rss;
      best = std::move(fits);
    }
  }
  double sum = 0;
  int clear = 0;
  for (size_t i = 0; i < limbs.size(); ++i)
    if (best[i].clear) {
      sum += best[i].at - limbs[i].peak;
      ++clear;
    }
  if (clear == 0) return std::nullopt;
  return sum / clear;
}

void RefineLimbsForShading(const StereoPair& pair, const std::array<FitView, 2>& views,
                           const FitOptions& fit, const LocateOptions& opt, const FitOutcome& f,
                           CylinderResult* res) {
  // Upright pipes only: a pipe lying on something has its own shadow or the table's contact
  // beside its lower limb, no even background, and on the site scenes its radius came out
  // worse for the move (docs/locator-site-scenes.md).
  if (!(opt.max_limb_shading_px > 0) || !f.ok || std::abs(res->axis.z()) < opt.upright_axis_cos)
    return;
  std::vector<LimbProfile> limbs;
  for (int v = 0; v < 2; ++v)
    for (auto& limb :
         LimbProfiles(v ? pair.right : pair.left, *views[v].camera, *views[v].gradients, f.params,
                      views[v].hidden, fit.min_gradient))
      if (limb) limbs.push_back(std::move(*limb));
  const std::optional<double> shift = LimbEdgeShift(limbs, kMinLimbStep);
  if (!shift) return;
  std::array<FitView, 2> shaded = views;
  for (FitView& v : shaded)
    v.limb_shift_px = std::clamp(*shift, -opt.max_limb_shading_px, opt.max_limb_shading_px);
  FitOptions last = fit;
  last.first_outer = std::max(0, fit.outer_iterations - 1);
  InnerEdgesFn inner;
  if (opt.cylinder_inner_edges) inner = CylinderInnerEdges;
  const FitOutcome g = FitSilhouette(CylinderOutline, f.params, shaded, last, inner);
  if (!g.ok) return;
  const CylinderResult c = CylinderFromFit(g.params, g.covariance);
  spdlog::debug(
      "locate: limbs moved out {:.3f} px for the side's shading ({} limbs): radius "
      "{:.4f} against {:.4f}",
      *shift, limbs.size(), c.radius, res->radius);
  res->radius = c.radius;
}

SideShading MeasureSideShading(const cv::Mat& image, const geometry::ProjectiveCamera& camera,
                               const Eigen::VectorXd& params,
                               const std::vector<std::vector<Eigen::Vector2d>>& hidden,
                               bool half_pixel_bins) {
  SideShading out;
  const Profile p = SampleProfile(image, camera, params, hidden, half_pixel_bins);
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
  const Eigen::VectorXd coef = A.colPivHouseholderQr().solve(b);
  out.smooth_rss = (A * coef - b).squaredNorm();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int k = 0; k < bins; ++k) {
    const double a = p.angle[k];
    const double g = coef[0] + coef[1] * std::cos(a) + coef[2] * std::sin(a) +
                     coef[3] * std::cos(2 * a) + coef[4] * std::sin(2 * a);
    lo = std::min(lo, g);
    hi = std::max(hi, g);
  }
  out.smooth_range = hi - lo;
  out.mean = total / samples;
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
    if (rss < out.step_rss) {
      out.step_sine = 0.5 * (std::sin(p.angle[br - 1]) + std::sin(p.angle[br]));
      out.step_contrast = mr - ml;
    }
    out.step_rss = std::min(out.step_rss, rss);
  }
  out.bins = bins;
  out.measured = true;
  return out;
}

SideShape ClassifySide(const StereoPair& pair, const Eigen::VectorXd& params,
                       const std::array<FitView, 2>& views, const LocateOptions& options) {
  int flat = 0, creased = 0, clearly_round = 0, even = 0, faint = 0;
  for (int v = 0; v < 2; ++v) {
    const SideShading sh =
        MeasureSideShading(v ? pair.right : pair.left, v ? *pair.right_camera : *pair.left_camera,
                           params, views[v].hidden, options.side_half_pixel_bins);
    if (!sh.measured) return SideShape::kUnmeasured;
    spdlog::debug(
        "locate: the side in the {} image shades {:.1f} times better round than flat, "
        "{:.1f} times better creased than round; grey {:.1f}, round over {:.1f}, {} bins",
        v ? "right" : "left", sh.flat_rss / std::max(sh.smooth_rss, 1e-9),
        sh.smooth_rss / std::max(sh.step_rss, 1e-9), sh.mean, sh.smooth_range, sh.bins);
    if (sh.smooth_rss > options.crease_gain * sh.step_rss)
      ++creased;
    else if (sh.flat_rss < options.flat_side_gain * sh.smooth_rss)
      ++flat;
    else if (sh.flat_rss >= options.round_side_gain * sh.smooth_rss)
      ++clearly_round;
    if (sh.flat_rss < options.even_side_gain * std::min(sh.smooth_rss, sh.step_rss)) ++even;
    if (sh.flat_rss < options.faint_round_side_gain * sh.smooth_rss) ++faint;
  }
  if (creased == 2) return SideShape::kCreased;
  if (clearly_round == 2) return SideShape::kClearlyRound;
  if (even == 2) return SideShape::kEven;
  if (flat + creased == 2) return SideShape::kFlat;
  return faint > 0 ? SideShape::kFaintlyRound : SideShape::kRound;
}

namespace {

// A block seen as an upright cylinder across its extent: the same foot and top, a radius of
// its half width across the view from `eye`; and that horizontal across (up x toward eye).
struct BlockAcross {
  Eigen::VectorXd cylinder;
  Eigen::Vector3d across, toward;
  double half_width = 0;
};

// The block's four vertical edges, from its centre, horizontally: its bottom corners
// (BoxOutline's first four) lifted to the centre's height.
std::array<Eigen::Vector3d, 4> VerticalEdges(const Eigen::VectorXd& box) {
  const std::vector<Eigen::Vector3d> corners = BoxOutline(box);
  std::array<Eigen::Vector3d, 4> out;
  for (int i = 0; i < 4; ++i) {
    out[i] = corners[i] - box.head<3>();
    out[i].z() = 0;
  }
  return out;
}

BlockAcross AcrossBlock(const Eigen::VectorXd& box, const Eigen::Vector3d& eye) {
  BlockAcross b;
  const Eigen::Vector3d c = box.head<3>(), up = Eigen::Vector3d::UnitZ();
  const double half_height = 0.5 * box[5];
  b.toward = eye - c;
  b.toward.z() = 0;
  if (b.toward.norm() < 1e-9) return b;
  b.toward.normalize();
  b.across = up.cross(b.toward);
  for (const auto& edge : VerticalEdges(box))
    b.half_width = std::max(b.half_width, std::abs(edge.dot(b.across)));
  b.cylinder.resize(7);
  b.cylinder << c - half_height * up, c + half_height * up, b.half_width;
  return b;
}

// The offset across of the block's vertical edge nearest `eye`.
double NearestEdgeAcross(const Eigen::VectorXd& box, const BlockAcross& b) {
  double nearest = -std::numeric_limits<double>::infinity(), at = 0;
  for (const auto& edge : VerticalEdges(box))
    if (edge.dot(b.toward) > nearest) {
      nearest = edge.dot(b.toward);
      at = edge.dot(b.across);
    }
  return at;
}

}  // namespace

std::optional<double> FaceCrease(const StereoPair& pair, const Eigen::VectorXd& box,
                                 const std::array<FitView, 2>& views, const LocateOptions& opt) {
  const BlockAcross b = AcrossBlock(box, pair.left_camera->Center());
  if (b.half_width <= 0) return std::nullopt;
  std::array<double, 2> at{};
  for (int v = 0; v < 2; ++v) {
    const SideShading sh =
        MeasureSideShading(v ? pair.right : pair.left, v ? *pair.right_camera : *pair.left_camera,
                           b.cylinder, views[v].hidden, opt.side_half_pixel_bins);
    if (!sh.measured || !(sh.flat_rss > opt.face_crease_gain * sh.step_rss) ||
        std::abs(sh.step_contrast) < opt.min_face_crease_step)
      return std::nullopt;
    at[v] = sh.step_sine;
  }
  spdlog::debug("locate: the block's face steps at {:.2f} and {:.2f} of its half width across",
                at[0], at[1]);
  if (std::abs(at[0] - at[1]) > opt.face_crease_agree) return std::nullopt;
  return 0.5 * (at[0] + at[1]) * b.half_width;
}

bool EdgeAtCrease(const Eigen::VectorXd& box, double crease, const Eigen::Vector3d& eye,
                  const LocateOptions& opt) {
  const BlockAcross b = AcrossBlock(box, eye);
  return b.half_width > 0 &&
         std::abs(crease - NearestEdgeAcross(box, b)) <= opt.face_crease_agree * b.half_width;
}

std::vector<Eigen::VectorXd> CreaseStarts(const Eigen::VectorXd& box, double crease,
                                          const Eigen::Vector3d& camera_centre) {
  const BlockAcross b = AcrossBlock(box, camera_centre);
  std::vector<Eigen::VectorXd> starts;
  const double left = crease + b.half_width, right = b.half_width - crease;
  if (b.half_width <= 0 || left <= 0 || right <= 0) return starts;
  // The nearest edge in front of the fitted block's front, at the crease.
  double front = 0;
  for (const auto& e : VerticalEdges(box)) front = std::max(front, e.dot(b.toward));
  const Eigen::Vector3d edge = box.head<3>() + crease * b.across + front * b.toward;
  for (const double turn_deg : kCreaseTurnsDeg) {
    const double t = turn_deg * M_PI / 180;
    // The left face recedes from the edge leftward at t to the view's perpendicular, the
    // right one rightward, square to it.
    const Eigen::Vector3d e1 = -std::cos(t) * b.across - std::sin(t) * b.toward;
    const Eigen::Vector3d e2 = std::sin(t) * b.across - std::cos(t) * b.toward;
    const double left_face = left / std::cos(t), right_face = right / std::sin(t);
    double a = left_face, c = right_face;
    double yaw = std::atan2(e1.y(), e1.x());
    // Folded into (-45, 45] degrees: a quarter turn swaps the sizes.
    while (yaw > M_PI / 4) {
      yaw -= M_PI / 2;
      std::swap(a, c);
    }
    while (yaw <= -M_PI / 4) {
      yaw += M_PI / 2;
      std::swap(a, c);
    }
    Eigen::VectorXd st(7);
    st << edge + 0.5 * (left_face * e1 + right_face * e2), a, c, box[5], yaw;
    starts.push_back(st);
  }
  return starts;
}

}  // namespace igms::object
