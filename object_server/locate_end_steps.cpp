// A fitted pipe's ends from where its limbs end in both images (locate_steps.h:
// EndsFromLimbs): the silhouette's ends, for an end no edge of the fit holds. A fitted block's
// top from where its sides' edges end (TopFromSides): below a pipe resting on it. And the
// found solid's sizes judged determined by their sigmas (CheckBoxSizesDetermined,
// CheckCylinderLengthDetermined).
#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "object_server/locate_steps.h"
#include "object_server/silhouette_fit_steps.h"
#include "object_server/solid_models.h"

namespace igms::object {
namespace {

// The parameter t of the point p0 + t (p1 - p0) whose projection lies `s` px from p0's along
// the image axis (secant steps from the ends: the projection is not quite linear along it);
// nullopt when a point does not project.
std::optional<double> AxisParameterAt(const geometry::ProjectiveCamera& camera,
                                      const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                      double s) {
  const auto q0 = camera.Project(p0), q1 = camera.Project(p1);
  if (!q0 || !q1 || (*q1 - *q0).norm() < 1e-9) return std::nullopt;
  const Eigen::Vector2d dir = (*q1 - *q0).normalized();
  double ta = 0, tb = 1, sa = 0, sb = (*q1 - *q0).norm();
  for (int it = 0; it < 3 && std::abs(sb - sa) > 1e-9; ++it) {
    const double t = ta + (s - sa) * (tb - ta) / (sb - sa);
    const auto q = camera.Project(p0 + t * (p1 - p0));
    if (!q) return std::nullopt;
    ta = tb;
    sa = sb;
    tb = t;
    sb = dir.dot(*q - *q0);
  }
  return tb;
}

// How far the pipe's limbs reach along its image axis (pixels from q0 along the unit `dir`;
// the far end's projection lies `length` px along): each limb, a line `radius_px` to either
// side of the axis, walked through the image from the middle outward while an edge across it
// (a gradient of at least min_gradient across the line, within kLimbBandPx of it) recurs
// within kLimbGapPx, and not out of `region` (when given). Per limb, how far it reaches back
// and on; nullopt when a limb has no edge at the middle.
std::optional<std::array<std::pair<double, double>, 2>> LimbExtent(
    const Gradients& gradients, const std::vector<Eigen::Vector2d>& region,
    const Eigen::Vector2d& q0, const Eigen::Vector2d& dir, double length, double radius_px,
    double min_gradient) {
  constexpr double kLimbGapPx = 4.0, kLimbBandPx = 2.0;
  const Eigen::Vector2d n(-dir.y(), dir.x());
  const auto edge_at = [&](double s, double side) {
    const Eigen::Vector2d on = q0 + s * dir + side * radius_px * n;
    if (region.size() >= 3 && SignedDistance(region, on) > 0) return false;
    for (double o = -kLimbBandPx; o <= kLimbBandPx; o += 0.5)
      if (std::abs(gradients.At(on + o * n).dot(n)) >= min_gradient) return true;
    return false;
  };
  std::array<std::pair<double, double>, 2> limbs;
  for (int l = 0; l < 2; ++l) {
    const double side = l ? 1.0 : -1.0, mid = 0.5 * length;
    if (!edge_at(mid, side) && !edge_at(mid - 1, side) && !edge_at(mid + 1, side))
      return std::nullopt;
    for (const double step : {-1.0, 1.0}) {
      double last = mid;
      for (double s = mid + step; std::abs(s - last) <= kLimbGapPx; s += step) {
        if (s < -length || s > 2 * length) break;
        if (edge_at(s, side)) last = s;
      }
      (step < 0 ? limbs[l].first : limbs[l].second) = last;
    }
  }
  return limbs;
}

// How far up a block's side (pixels from its bottom corner q0 along the unit `dir`, the side
// `length` px long) its edge runs: walked up from the middle while an edge along the side (a
// gradient of at least min_gradient within 20 degrees of the side's normal, within 2 px of
// it) recurs within 4 px. nullopt when there is no edge at the middle.
std::optional<double> SideEdgeEnd(const Gradients& gradients, const Eigen::Vector2d& q0,
                                  const Eigen::Vector2d& dir, double length, double min_gradient) {
  constexpr double kGapPx = 4.0, kBandPx = 2.0;
  const Eigen::Vector2d n(-dir.y(), dir.x());
  const double cos_max = std::cos(20 * M_PI / 180);
  const auto edge_at = [&](double s) {
    for (double o = -kBandPx; o <= kBandPx; o += 0.5) {
      const Eigen::Vector2d g = gradients.At(q0 + s * dir + o * n);
      const double across = std::abs(g.dot(n));
      if (across >= min_gradient && across >= cos_max * g.norm()) return true;
    }
    return false;
  };
  const double mid = 0.5 * length;
  if (!edge_at(mid) && !edge_at(mid - 1) && !edge_at(mid + 1)) return std::nullopt;
  double last = mid;
  for (double s = mid + 1; s - last <= kGapPx && s <= 2 * length; s += 1)
    if (edge_at(s)) last = s;
  return last;
}

// The fitted cylinder's outline drawn again in both views, after its ends moved.
void DrawCylinderOutline(const std::array<FitView, 2>& views, FitOutcome* f) {
  for (int v = 0; v < 2; ++v) {
    ViewOutline o;
    f->outline[v].clear();
    if (ProjectOutline(CylinderOutline(f->params), *views[v].camera, o))
      for (const int i : o.hull) f->outline[v].push_back(o.px[i]);
  }
}

// Measures g . params to `innovation` away from where the fit has it, with deviation `sigma`:
// a Kalman update of the parameters and their covariance.
void MeasureAlong(const Eigen::VectorXd& g, double innovation, double sigma, FitOutcome* f) {
  const Eigen::VectorXd cg = f->covariance * g;
  const double spread = g.dot(cg) + sigma * sigma;
  if (!(spread > 0)) return;  // an exact measurement of what the fit already holds exactly
  const Eigen::VectorXd gain = cg / spread;
  f->params += gain * innovation;
  f->covariance -= gain * cg.transpose();
}

// A fitted pipe's axis from `from` to `to` as a view sees it: its start, unit direction and
// length in the image, and its radius in pixels (the farthest of the view's fitted outline
// from the axis). Nullopt when an end does not project or the axis is under 8 px long.
struct AxisInImage {
  Eigen::Vector2d q0, dir;
  double length = 0, radius_px = 0;
};
std::optional<AxisInImage> AxisIn(const geometry::ProjectiveCamera& camera,
                                  const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                                  const std::vector<Eigen::Vector2d>& outline) {
  const auto q0 = camera.Project(from), q1 = camera.Project(to);
  if (!q0 || !q1 || (*q1 - *q0).norm() < 8) return std::nullopt;
  AxisInImage a;
  a.q0 = *q0;
  a.length = (*q1 - *q0).norm();
  a.dir = (*q1 - *q0) / a.length;
  const Eigen::Vector2d n(-a.dir.y(), a.dir.x());
  for (const auto& h : outline) a.radius_px = std::max(a.radius_px, std::abs(n.dot(h - *q0)));
  return a;
}

}  // namespace

bool BackgroundChangesBeside(const Gradients& gradients, const Eigen::Vector2d& end,
                             const Eigen::Vector2d& dir, double radius_px, double min_gradient) {
  // The blur carries a limb's edge a few pixels either side of the change.
  constexpr int kBackgroundReachPx = 5;
  const Eigen::Vector2d n(-dir.y(), dir.x());
  for (const double side : {-1.0, 1.0})
    for (int k = -kBackgroundReachPx; k <= kBackgroundReachPx; ++k) {
      const Eigen::Vector2d q = end + k * dir + side * (radius_px + 3) * n;
      if (std::abs(gradients.At(q).dot(dir)) > min_gradient) return true;
    }
  return false;
}

void EndsFromLimbs(const std::array<FitView, 2>& views, const FitOptions& fit,
                   const LocateOptions& opt, FitOutcome* f) {
  if (!f->ok || f->params.size() != 7 || f->covariance.rows() != 7 || !f->params.allFinite())
    return;
  const Eigen::Vector3d p0 = f->params.segment<3>(0), p1 = f->params.segment<3>(3);
  const double len = (p1 - p0).norm(), radius = std::abs(f->params[6]);
  if (len < 1e-9 || radius < 1e-9) return;
  const Eigen::Vector3d a = (p1 - p0) / len;
  // Per end, the axis parameter (0 at p0, 1 at p1) each view's limbs reach (kKeep: the view
  // says nothing of it), and a pixel's length along the axis in each view.
  std::array<std::vector<double>, 2> reach;
  constexpr double kKeep = std::numeric_limits<double>::quiet_NaN();
  constexpr double kBorderPx = 5;
  std::array<double, 2> unit{0, 0};
  std::array<std::optional<std::pair<double, double>>, 2> between;  // limbs' end, marks' exit
  for (int v = 0; v < 2; ++v) {
    const geometry::ProjectiveCamera& cam = *views[v].camera;
    const auto axis = AxisIn(cam, p0, p1, f->outline[v]);
    if (!axis) return;
    const Eigen::Vector2d q0 = axis->q0, dir = axis->dir, n(-dir.y(), dir.x());
    const double length = axis->length, radius_px = axis->radius_px;
    const auto limbs = LimbExtent(*views[v].gradients, views[v].region, q0, dir, length, radius_px,
                                  fit.min_gradient);
    if (!limbs) return;
    unit[v] = len / length;
    // Limbs that run on to within kBorderPx of the marks' border say nothing of where the
    // pipe ends (a neighbour's edge in line with one can carry them there).
    const auto at_border = [&](double s_end, double out) {
      if (views[v].region.size() < 3) return false;
      for (const double side : {-1.0, 1.0}) {
        const Eigen::Vector2d past = q0 + (s_end + kBorderPx * out) * dir + side * radius_px * n;
        if (SignedDistance(views[v].region, past) > 0) return true;
      }
      return false;
    };
    for (int end = 0; end < 2; ++end) {
      const double out = end == 0 ? -1.0 : 1.0;  // away from the pipe's middle
      // The farther-reaching limb sets the end (the other may fade first, shaded or against
      // the table); when a neighbour's edge carries it on to the marks' border, the other
      // limb, if it stops short of there: the other view must agree with it (below).
      std::array<double, 2> s_limb{};
      for (int l = 0; l < 2; ++l) s_limb[l] = end == 0 ? (*limbs)[l].first : (*limbs)[l].second;
      const int far = out * (s_limb[1] - s_limb[0]) > 0 ? 1 : 0;
      double s_end = s_limb[far];
      if (at_border(s_end, out) && !at_border(s_limb[1 - far], out)) s_end = s_limb[1 - far];
      const auto t = AxisParameterAt(cam, p0, p1, s_end);
      if (!t) return;
      // Where the background changes across the axis beside a limb's end (the table's far
      // edge behind an upright pipe), the limbs may stop because the pipe turns to the
      // background's shade there, not because it ends.
      const bool background_changes = BackgroundChangesBeside(*views[v].gradients, q0 + s_end * dir,
                                                              dir, radius_px, fit.min_gradient);
      const bool border = at_border(s_end, out);
      reach[end].push_back(background_changes || border ? kKeep : *t);
      // In the left image, where the limbs stop at a change of the background, the pipe ends
      // between there and where its axis leaves the marks.
      if (v != 0 || !background_changes || border || views[v].region.size() < 3) continue;
      double s = s_end;
      while (std::abs(s - s_end) < 4 * length &&
             SignedDistance(views[v].region, q0 + (s + out) * dir) <= 0)
        s += out;
      if (const auto t_exit = AxisParameterAt(cam, p0, p1, s)) between[end] = {*t, *t_exit};
    }
  }
  const double px = std::max(unit[0], unit[1]);  // world length of a pixel along the axis
  Eigen::VectorXd x = f->params;
  Eigen::MatrixXd cov = f->covariance;
  bool moved = false;
  for (int end = 0; end < 2; ++end) {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(7);
    g.segment<3>(Eigen::Index{3} * end) = a;
    const double end_sigma = std::sqrt(std::max(0.0, g.dot(cov * g)));
    if (end_sigma >= opt.unheld_end_sigma && between[end]) {
      // An unheld end between the limbs' end and the marks' border stays where the fit left
      // it, with the sigma of its distance to an even spread over the farther of the two.
      const auto [limbs, exit] = *between[end];
      const double spread = std::max(std::abs(exit - limbs), std::abs(end - limbs)) * len;
      const Eigen::VectorXd cg = cov * g;
      cov -= cg * cg.transpose() / (g.dot(cg) + spread * spread / 3);
      moved = true;
      continue;
    }
    // Both views must agree on where the limbs end.
    if (std::isnan(reach[end][0]) || std::isnan(reach[end][1]) ||
        std::abs(reach[end][0] - reach[end][1]) * len > opt.limb_end_agree_px * px)
      continue;
    const double t = 0.5 * (reach[end][0] + reach[end][1]);
    if (end_sigma < opt.unheld_end_sigma) {
      // A held end of an upright pipe the limbs run clearly past in both views held on an
      // edge inside the silhouette (a band of another shade across the pipe): what held it
      // is forgotten. (A lying pipe's limbs run on along the table's and its supports' edges.)
      constexpr double kForgottenSigma = 100.0;  // world units, as an unheld end's
      const double beyond = (end == 0 ? -t : t - 1) * len;
      if (std::abs(a.z()) < opt.upright_axis_cos || beyond < 3 * px || beyond < 3 * end_sigma)
        continue;
      cov += g * g.transpose() * (kForgottenSigma * kForgottenSigma);
    }
    const Eigen::Vector3d end_point = p0 + t * (p1 - p0);
    x.segment<3>(Eigen::Index{3} * end) = end_point;
    // The end measured along the axis to limb_end_sigma_px: a Kalman update of the covariance.
    const double var = std::pow(opt.limb_end_sigma_px * px, 2);
    const Eigen::VectorXd cg = cov * g;
    cov -= cg * cg.transpose() / (g.dot(cg) + var);
    moved = true;
  }
  if (!moved) return;
  f->params = x;
  f->covariance = cov;
  DrawCylinderOutline(views, f);
}

bool FootAtBackgroundChange(const std::array<FitView, 2>& views, const FitOptions& fit,
                            const FitOutcome& f) {
  if (!f.ok || f.params.size() != 7 || !f.params.allFinite() || f.outline[0].empty()) return false;
  const Eigen::VectorXd& x = f.params;
  const Eigen::Index foot = x[2] < x[5] ? 0 : 3;
  const auto axis =
      AxisIn(*views[0].camera, x.segment<3>(foot), x.segment<3>(3 - foot), f.outline[0]);
  return axis && BackgroundChangesBeside(*views[0].gradients, axis->q0, axis->dir, axis->radius_px,
                                         fit.min_gradient);
}

void FootOnFloor(const std::array<FitView, 2>& views, const LocateOptions& opt, FitOutcome* f) {
  if (!opt.floor_height || !f->ok || f->params.size() != 7 || f->covariance.rows() != 7 ||
      !f->params.allFinite())
    return;
  Eigen::VectorXd& x = f->params;
  const Eigen::Index foot = x[2] < x[5] ? 0 : 3;  // the foot's first coordinate
  const Eigen::Vector3d base = x.segment<3>(foot), top = x.segment<3>(3 - foot);
  const double len = (top - base).norm(), floor = *opt.floor_height;
  if (!(len > 1e-9) || top.z() - base.z() < opt.upright_axis_cos * len || top.z() <= floor ||
      base.z() > floor + opt.pipe_floor_gap)
    return;
  const Eigen::Vector3d up = (top - base) / len;
  Eigen::VectorXd g = Eigen::VectorXd::Zero(7);
  g.segment<3>(foot) = up;
  if (base.z() >= floor - opt.floor_sink) {
    // Standing on the floor: the floor holds the foot there, to pipe_floor_gap along the axis,
    // whatever edge the foot shows (none in the table's shade, or behind what stands in front).
    MeasureAlong(g, (floor - base.z()) / up.z(), opt.pipe_floor_gap, f);
  } else {
    // In the floor: moved up onto it, and measured there to floor_sink along the axis.
    x.segment<3>(foot) = base + (floor - base.z()) / up.z() * up;
    MeasureAlong(g, 0.0, opt.floor_sink, f);
  }
  DrawCylinderOutline(views, f);
}

std::optional<Eigen::VectorXd> TopFromSides(const std::array<FitView, 2>& views,
                                            const FitOptions& fit, const LocateOptions& opt,
                                            const FitOutcome& f) {
  if (!f.ok || f.params.size() != 7 || !f.params.allFinite()) return std::nullopt;
  const Eigen::VectorXd& x = f.params;
  const Eigen::Vector3d centre = x.head<3>(), size = x.segment<3>(3).cwiseAbs();
  Eigen::VectorXd upright = x;  // its corners with bit 2 clear at the bottom
  upright.segment<3>(3) = size;
  const std::vector<Eigen::Vector3d> corners = BoxOutline(upright);
  constexpr double kMinSidePx = 8, kMinShortfallPx = 3;
  // Per silhouette side in either view: the share of the height its edge reaches (0 at the
  // bottom, 1 at the top) and the pixels it stops short of the top.
  std::vector<std::pair<double, double>> ends;
  for (int v = 0; v < 2; ++v) {
    const geometry::ProjectiveCamera& cam = *views[v].camera;
    // The vertical edges' bottoms and tops; the two outermost across the image are the sides.
    std::array<Eigen::Vector3d, 4> bottom, top;
    std::array<double, 4> across{};
    const auto c0 = cam.Project(centre), c1 = cam.Project(centre + Eigen::Vector3d::UnitZ());
    if (!c0 || !c1 || (*c1 - *c0).norm() < 1e-9) return std::nullopt;
    const Eigen::Vector2d up = (*c1 - *c0).normalized(), normal(-up.y(), up.x());
    for (int k = 0; k < 4; ++k) {
      bottom[k] = corners[k];
      top[k] = corners[k + 4];
      const auto q = cam.Project(0.5 * (bottom[k] + top[k]));
      if (!q) return std::nullopt;
      across[k] = normal.dot(*q);
    }
    const auto [lo, hi] = std::minmax_element(across.begin(), across.end());
    for (const auto side : {lo, hi}) {
      const auto k = static_cast<size_t>(side - across.begin());
      const auto q0 = cam.Project(bottom[k]), q1 = cam.Project(top[k]);
      if (!q0 || !q1) return std::nullopt;
      const double length = (*q1 - *q0).norm();
      if (length < kMinSidePx) return std::nullopt;
      // A side a known solid in front hides in part says nothing of where it ends.
      bool hidden = false;
      for (const auto& h : views[v].hidden)
        for (const double t : {0.25, 0.5, 0.75, 1.0})
          if (SignedDistance(h, *q0 + t * (*q1 - *q0)) < 2) hidden = true;
      if (hidden) continue;
      const Eigen::Vector2d dir = (*q1 - *q0) / length;
      const auto end = SideEdgeEnd(*views[v].gradients, *q0, dir, length, fit.min_gradient);
      if (!end) return std::nullopt;  // no edge half way up: nothing to say
      const auto t = AxisParameterAt(cam, bottom[k], top[k], *end);
      if (!t) return std::nullopt;
      ends.emplace_back(*t, length - *end);
    }
  }
  if (ends.size() < 2) return std::nullopt;
  // The top is where the second-highest side ends: a neighbour's edge in line with one side
  // carries it on up.
  std::sort(ends.rbegin(), ends.rend());
  const auto [reach, shortfall_px] = ends[1];
  if (reach <= 0 || reach >= opt.box_side_reach || shortfall_px < kMinShortfallPx)
    return std::nullopt;
  Eigen::VectorXd lowered = x;
  lowered[2] = centre.z() - 0.5 * size.z() * (1 - reach);
  lowered[5] = reach * size.z();
  spdlog::debug("locate: the sides' edges reach {:.2f} of the block's height", reach);
  return lowered;
}

// A size the images leave open (a block's depth behind a pipe resting on it, read off the
// pipe's far limb) would be a guess, however well the outline fits.
std::optional<StepFailure> CheckBoxSizesDetermined(const BoxResult& box, const LocateOptions& opt) {
  const char* axis_names[3] = {"width", "depth", "height"};
  for (int k = 0; k < 3; ++k)
    if (box.size_sigma[k] > opt.max_box_size_sigma)
      return StepFailure{Failure::kFitFailed,
                         std::string("the images do not determine the box's ") + axis_names[k] +
                             " (" + FormatFixed(box.size[k]) + " +/- " +
                             FormatFixed(box.size_sigma[k]) + ")"};
  return std::nullopt;
}

// A pipe's length the images leave open (an end no edge and no limb holds, in clutter) is a
// guess as much as a block's: it comes out inches off. So is one shorter than its radius: the
// end cap alone, fitted on a pipe pointing at the cameras.
std::optional<StepFailure> CheckCylinderLengthDetermined(const CylinderResult& c,
                                                         const LocateOptions& opt) {
  if (c.height < c.radius)
    return StepFailure{Failure::kFitFailed,
                       "the fitted cylinder is " + FormatFixed(c.height) +
                           " long, under its radius (" + FormatFixed(c.radius) +
                           "): a pipe's end seen, not its length (is it pointing at the cameras?)"};
  if (!(c.height_sigma > opt.max_box_size_sigma)) return std::nullopt;
  return StepFailure{Failure::kFitFailed, "the images do not determine the cylinder's length (" +
                                              FormatFixed(c.height) + " +/- " +
                                              FormatFixed(c.height_sigma) + ")"};
}

}  // namespace igms::object
