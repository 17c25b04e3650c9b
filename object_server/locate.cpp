#include "object_server/locate.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "object_server/image_ops.h"
#include "object_server/locate_steps.h"
#include "object_server/silhouette_fit.h"
#include "object_server/solid_models.h"

namespace igms::object {
namespace {

using Clock = std::chrono::steady_clock;

// With the known solids in front of part of the marks named, for the operator (what may hide
// the object, or lend it edges).
LocateResult Fail(LocateResult r, const StepFailure& failure, const std::string& in_front) {
  r.found = false;
  r.reason = failure.reason;
  r.detail = failure.detail;
  if (!in_front.empty()) r.detail += " (in front of part of the marks: " + in_front + ")";
  return r;
}

// A model that lies mostly inside a known solid, or takes one in, is that solid found again:
// the object marked is hidden behind it, or is it. Solids cannot share their volume.
std::optional<StepFailure> CheckNotKnown(const LocateResult& res,
                                         const std::vector<KnownShape>& known,
                                         const LocateOptions& opt) {
  const bool cylinder = res.type == SolidType::kCylinder;
  const Eigen::VectorXd x = KnownFromResult(res, "").params;
  for (const KnownShape& k : known) {
    if (k.params.size() != 7 || !k.params.allFinite()) continue;
    const bool k_cylinder = k.type == SolidType::kCylinder;
    const double share = std::max(ShareInside(cylinder, x, k_cylinder, k.params),
                                  ShareInside(k_cylinder, k.params, cylinder, x));
    if (share > opt.max_shared_volume)
      return StepFailure{Failure::kAlreadyModelled,
                         "the fitted model is " + k.name + ", already in the database (" +
                             FormatFixed(100 * share, 0) +
                             "% of one lies inside the other): the object is hidden behind it, "
                             "or is it"};
  }
  return std::nullopt;
}

// A cylinder thinner than min_radius_px is one edge taken for a pipe (a block's side).
std::optional<StepFailure> CheckCylinderWidth(const CylinderResult& c,
                                              const geometry::ProjectiveCamera& left_camera,
                                              const LocateOptions& opt) {
  const auto centre_px = left_camera.Project(c.center);
  if (!centre_px) return std::nullopt;
  const double depth = left_camera.Depth(c.center);
  const double unit = (PointOnPixelRay(left_camera, *centre_px + Eigen::Vector2d(1, 0), depth) -
                       PointOnPixelRay(left_camera, *centre_px, depth))
                          .norm();
  if (c.radius >= opt.min_radius_px * unit) return std::nullopt;
  return StepFailure{Failure::kFitFailed, "the fitted cylinder is " +
                                              FormatFixed(c.radius / unit, 1) +
                                              " px in radius: a single edge, not a pipe"};
}

// Where the outline can lie in each view (OutlineRegions): a block's far side lies at most the
// marked region's diagonal behind its front, a pipe pointing away from the cameras further
// (cylinder_depth_reach diagonals).
void BoundByMarks(const MarkedRegion& marks, const StereoPair& pair, double depth0, bool cylinder,
                  const LocateOptions& opt, std::array<FitView, 2>* views) {
  const auto corner = [&](size_t i) {
    return PointOnPixelRay(*pair.left_camera, Eigen::Vector2d(marks.hull[i].x, marks.hull[i].y),
                           depth0);
  };
  double diagonal = 0;
  for (size_t i = 0; i < marks.hull.size(); ++i)
    for (size_t j = i + 1; j < marks.hull.size(); ++j)
      diagonal = std::max(diagonal, (corner(i) - corner(j)).norm());
  const double slack = 0.5 * opt.depth_tolerance;
  const double reach = cylinder ? opt.cylinder_depth_reach : 1.0;
  auto regions = OutlineRegions(marks, pair, std::max(0.5 * depth0, depth0 - slack),
                                depth0 + slack + reach * diagonal, opt);
  (*views)[0].region = std::move(regions[0]);
  (*views)[1].region = std::move(regions[1]);
}

// Each start also stretched along its axis to fill the marks (CylinderStretchedToMarks).
void AddStretched(const MarkedRegion& marks, const geometry::ProjectiveCamera& left_camera,
                  const LocateOptions& opt, std::vector<Eigen::VectorXd>* starts) {
  const size_t n = starts->size();
  for (size_t i = 0; i < n; ++i)
    if (auto st = CylinderStretchedToMarks((*starts)[i], marks, left_camera, opt.stretch_margin))
      starts->push_back(*st);
}

// A cylinder's fit parameters lying within raised_pipe_max_tilt_deg of the horizontal.
bool LyingPipe(const Eigen::VectorXd& params, const LocateOptions& opt) {
  const Eigen::Vector3d axis = params.segment<3>(3) - params.segment<3>(0);
  return std::abs(axis.z()) <= std::sin(opt.raised_pipe_max_tilt_deg * M_PI / 180) * axis.norm();
}

// A pipe standing within acos(upright_axis_cos) of the vertical.
bool UprightPipe(const Eigen::VectorXd& params, const LocateOptions& opt) {
  const Eigen::Vector3d axis = params.segment<3>(3) - params.segment<3>(0);
  return std::abs(axis.z()) >= opt.upright_axis_cos * axis.norm() && axis.norm() > 1e-9;
}

// A cylinder fit that collapsed to a single edge (under min_radius_px in the reference view).
bool Collapsed(const FitOutcome& o, const std::array<FitView, 2>& views, const LocateOptions& opt) {
  return o.ok && CheckCylinderWidth(CylinderFromFit(o.params, o.covariance), *views[0].camera, opt);
}

// A raised pipe's starts (CylinderStarts), fitted only when the other starts' fit is poor
// (poor_fit_score), leaves the marks or collapsed to a single edge, and kept when they fit a
// pipe lying within raised_pipe_max_tilt_deg of the horizontal better (at any tilt, with
// `any_tilt`: a pipe leaning across its block), or hold a width where the other collapsed.
void TryRaisedPipe(const std::vector<Eigen::VectorXd>& raised, const std::array<FitView, 2>& views,
                   const FitOptions& fit, const LocateOptions& opt, const PlausibleFn& plausible,
                   FitOutcome* f, bool any_tilt = false) {
  const auto collapsed = [&](const FitOutcome& o) { return Collapsed(o, views, opt); };
  if (raised.empty() ||
      (f->ok && plausible(*f) && FitScore(*f) <= opt.poor_fit_score && !collapsed(*f)))
    return;
  FitOutcome g = FitCylinder(raised, views, fit, opt, plausible);
  if (any_tilt) spdlog::debug("locate: a pipe leaning across its block scores {:.3f}", FitScore(g));
  if (!g.ok || (!any_tilt && !LyingPipe(g.params, opt))) return;
  if (any_tilt && collapsed(g) && f->ok && !collapsed(*f)) return;  // onto one limb line
  if (!f->ok || (collapsed(*f) && !collapsed(g)) || BetterFit(g, *f, plausible)) *f = std::move(g);
}

// A fit collapsed onto one limb (CheckCylinderWidth) tried again from the pipes that limb
// bounds (PipesBesideLimb); kept when one holds a width.
void TryBesideLimb(const std::array<Eigen::Vector3d, 4>& marks, const std::array<FitView, 2>& views,
                   const FitOptions& fit, const LocateOptions& opt, const PlausibleFn& plausible,
                   FitOutcome* f) {
  const auto collapsed = [&](const FitOutcome& o) { return Collapsed(o, views, opt); };
  if (!collapsed(*f)) return;
  const std::vector<Eigen::VectorXd> starts = PipesBesideLimb(f->params, marks, *views[0].camera);
  if (starts.empty()) return;
  FitOutcome g = FitCylinder(starts, views, fit, opt, plausible);
  spdlog::debug("locate: collapsed onto a limb; fitted beside it, {} scoring {:.3f}",
                g.ok && !collapsed(g) ? "a pipe" : "collapsed again", FitScore(g));
  if (g.ok && !collapsed(g)) *f = std::move(g);
}

void HideBehindKnown(const std::vector<KnownInFront>& in_front, std::array<FitView, 2>* views) {
  for (const KnownInFront& k : in_front)
    for (int v = 0; v < 2; ++v) (*views)[v].hidden.push_back(k.outline[v]);
}

// What a type's fit starts from (Locate's steps 1-3).
struct FitContext {
  const LocateInput& in;
  const StereoPair& pair;
  const MarkedRegion& marks;
  const Boundary& boundary;
  const DepthSearch& search;
  double depth0;
  const Gradients& grad_left;
  const Gradients& grad_right;
  const std::vector<KnownInFront>& in_front;
  const LocateOptions& opt;
  const PlausibleFn& plausible;
};

// A block fitted lower that explains the edges (under max_fit_score) but with a size nothing
// holds (its top face hidden under what rests on it, too thin in the image for its near edge
// to be measured): said when the fit up to the top is refused, so the operator knows why.
struct OpenLowered {
  double score = 0;  // FitScore in reference pixels
  int axis = 0;      // the open size: 0 width, 1 depth, 2 height
  double size = 0, sigma = 0;
};

// A block fitted again lower (LowerToSides, LowerByShares) replaces the fit if it fits better
// and its sizes are known to max_lowered_size_sigma; one that explains the edges with a size
// left open is remembered in `open`.
void KeepLowered(FitOutcome g, const char* how, const FitContext& c, FitOutcome* f,
                 std::optional<OpenLowered>* open) {
  if (!g.ok) return;
  const BoxResult box = BoxFromFit(g.params, g.covariance);
  int axis = 0;
  const double worst_sigma = box.size_sigma.maxCoeff(&axis);
  spdlog::debug("locate: fitted {}, it scores {:.3f} against {:.3f}, its sizes known to {:.2f}",
                how, FitScore(g), FitScore(*f), worst_sigma);
  const double score = FitScore(g, ScoreResidualScale(c.opt, c.pair.left.cols));
  if (worst_sigma > c.opt.max_lowered_size_sigma && score <= c.opt.max_fit_score &&
      (!*open || score < (*open)->score))
    *open = OpenLowered{score, axis, box.size[axis], worst_sigma};
  if (worst_sigma <= c.opt.max_lowered_size_sigma && BetterFit(g, *f, c.plausible))
    *f = std::move(g);
}

// A block fitted up to a pipe resting on it (TopFromSides) fitted again below the top its
// sides show: from there, and from the starts of the boundary below that top. Kept if it fits
// better and its sizes are known to max_lowered_size_sigma: with a pipe lying over its top,
// what holds its depth is scarce, and a pipe running back along it is easily taken for the
// top's far edge.
void LowerToSides(const FitContext& c, const std::array<FitView, 2>& views, const FitOptions& fit,
                  FitOutcome* f, std::optional<OpenLowered>* open) {
  const auto lowered = TopFromSides(views, fit, c.opt, *f);
  if (!lowered) return;
  // The boundary no higher than the lowered block's top face.
  const geometry::ProjectiveCamera& cam = c.in.left_camera;
  const Eigen::Vector3d centre = lowered->head<3>();
  const auto c0 = cam.Project(centre), c1 = cam.Project(centre + Eigen::Vector3d::UnitZ());
  if (!c0 || !c1 || (*c1 - *c0).norm() < 1e-9) return;
  const Eigen::Vector2d up = (*c1 - *c0).normalized();
  const std::vector<Eigen::Vector3d> corners = BoxOutline(*lowered);
  double top = -1e18;
  for (int k = 4; k < 8; ++k) {  // bit 2 set: the top face (its height is positive)
    const auto q = cam.Project(corners[k]);
    if (!q) return;
    top = std::max(top, up.dot(*q));
  }
  std::vector<cv::Point> below;
  for (const auto& p : c.boundary.pixels)
    if (up.dot(Eigen::Vector2d(p.x, p.y)) <= top + 1.5) below.push_back(p);
  std::vector<Eigen::VectorXd> starts;
  std::vector<Eigen::VectorXd> if_poor;
  if (below.size() >= 8) starts = BoxStarts(cam, below, c.depth0, &c.grad_left, &if_poor);
  if (starts.empty()) {  // FitBox starts from a world-aligned block
    Eigen::VectorXd aligned = *lowered;
    aligned[6] = 0;
    starts.push_back(aligned);
  }
  starts.push_back(*lowered);
  KeepLowered(FitBox(starts, views, fit, c.opt, c.plausible, if_poor), "below the sides' top", c, f,
              open);
}

// A block that would be refused as explaining the edges poorly, fitted again from itself
// lowered to lowered_shares of its height (its bottom kept): a pipe resting on it, or another
// object on top, carries the fit's top up to its own where the sides say nothing of the block's
// (TopFromSides). Kept as LowerToSides keeps its fit: if it fits better and its sizes are known
// to max_lowered_size_sigma (without that bound, blocks in line behind came in, inches deep).
void LowerByShares(const FitContext& c, const std::array<FitView, 2>& views, const FitOptions& fit,
                   FitOutcome* f, std::optional<OpenLowered>* open) {
  if (c.opt.lowered_shares.empty() || !f->ok || f->params.size() != 7 ||
      FitScore(*f, ScoreResidualScale(c.opt, c.pair.left.cols)) <= c.opt.max_fit_score)
    return;
  std::vector<Eigen::VectorXd> starts;
  const double height = std::abs(f->params[5]);
  for (const double share : c.opt.lowered_shares) {
    Eigen::VectorXd x = f->params;
    x[2] -= 0.5 * (1 - share) * height;
    x[5] = share * height;
    starts.push_back(x);
  }
  KeepLowered(FitBox(starts, views, fit, c.opt, c.plausible, {}), "lowered by shares", c, f, open);
}

// A solid fitted off the site's floor, fitted again standing on it under its top; kept if that
// fits better. An upright pipe's foot more than pipe_floor_gap off it (an object in front hides
// its foot, a shadow or the table's pattern holds it short, or the foot has the table's shade
// and no edge holds it) is kept standing on it when that scores better or is the plausible
// one; a rival pipe fitted against a block too. So is a block's bottom more than floor_gap off
// it, but only when standing scores better and is plausible: a block's foot in the table's
// shade leaves an implausible fit of its upper part, and a plausible block standing on the
// floor that fits worse was, on the held-out seeds, an upright pipe asked for as a block.
void StandOnFloor(const FitContext& c, bool cylinder, const std::array<FitView, 2>& views,
                  const FitOptions& fit, FitOutcome* f) {
  if (!c.opt.floor_height || !f->ok || f->params.size() != 7) return;
  const double floor = *c.opt.floor_height;
  const Eigen::VectorXd& x = f->params;
  Eigen::VectorXd standing = x;
  if (cylinder) {
    const Eigen::Vector3d axis = x.segment<3>(3) - x.segment<3>(0);
    if (!(axis.norm() > 1e-9) || std::abs(axis.z()) < c.opt.upright_axis_cos * axis.norm()) return;
    const int foot = x[2] < x[5] ? 0 : 3, top = 3 - foot;
    if (std::abs(x[foot + 2] - floor) <= c.opt.pipe_floor_gap) return;
    standing.segment<3>(foot) << x[top], x[top + 1], floor;
  } else {
    // Centre, size, yaw: the top kept, the bottom on the floor.
    const double top = x[2] + 0.5 * std::abs(x[5]), bottom = x[2] - 0.5 * std::abs(x[5]);
    if (std::abs(bottom - floor) <= c.opt.floor_gap || top <= floor + c.opt.floor_gap) return;
    standing[2] = 0.5 * (top + floor);
    standing[5] = top - floor;
  }
  FitOutcome g = cylinder ? FitCylinder({standing}, views, fit, c.opt, c.plausible)
                          : FitBox({standing}, views, fit, c.opt, c.plausible, {});
  spdlog::debug("locate: standing on the floor, it scores {:.3f} against {:.3f}", FitScore(g),
                FitScore(*f));
  if (!g.ok) return;
  const bool plausible = !c.plausible || c.plausible(g);
  // A pipe's foot where the background changes beside it (the table's far edge) may be held
  // there by that change: standing is kept up to background_foot_ratio times worse.
  const bool keep = cylinder ? BetterFit(g, *f, c.plausible) ||
                                   (plausible && FootAtBackgroundChange(views, fit, *f) &&
                                    FitScore(g) <= c.opt.background_foot_ratio * FitScore(*f))
                             : FitScore(g) < FitScore(*f) && plausible;
  if (keep) *f = std::move(g);
}

// One type's fit, whether that type was asked for or is the other one tried against it: its
// own edge angles and outline regions, its starts (a pipe's also stretched to fill the marks,
// and from a raised pipe's upper limb when the others fit poorly), and a pipe's ends from its
// limbs. Only a pipe asked for is also started from its boundary's upper part: fitted against
// a block asked for, a pipe on the block's top refused 4 right blocks of the tuning and
// held-out seeds as "a cylinder explains the outline about as well", and took 13 ms more.
// A pipe asked for whose fit collapsed onto one limb is fitted again beside it; a block fitted
// up to what rests on it, lower; an upright pipe, or a block asked for, off the site's floor,
// standing on it.
struct SolidFit {
  FitOutcome fit;
  FitOptions options;
  std::array<FitView, 2> views;
  std::optional<OpenLowered> open_lowered;  // a block's
};

// A block fitted as one face where two meet (FaceCrease) fitted again turned to the crease,
// kept if it explains the images better: a turned block's faces, fitted from square on, stay
// one face (the world-aligned fit comes first, FitBox), and its yaw and depth come out wrong.
void TurnToCrease(const FitContext& c, const std::array<FitView, 2>& views, const FitOptions& fit,
                  FitOutcome* f) {
  if (!(c.opt.face_crease_gain > 0) || !IsSolid(*f)) return;
  const Eigen::Vector3d eye = c.in.left_camera.Center();
  const auto crease = FaceCrease(c.pair, f->params, views, c.opt);
  if (!crease || EdgeAtCrease(f->params, *crease, eye, c.opt)) return;
  const auto starts = CreaseStarts(f->params, *crease, eye);
  if (starts.empty()) return;
  InnerEdgesFn inner;
  if (c.opt.box_inner_edges) inner = BoxInnerEdges;
  FitOutcome turned = FitFromStarts(BoxOutline, inner, starts, views, fit, c.plausible);
  spdlog::debug("locate: turned to the crease {:.2f} across: score {:.3f} against {:.3f}", *crease,
                FitScore(turned), FitScore(*f));
  if (IsSolid(turned) && BetterFit(turned, *f, c.plausible)) *f = std::move(turned);
}

SolidFit FitSolid(bool cylinder, const FitContext& c, bool asked) {
  SolidFit s;
  s.options = FitSettings(c.opt, c.boundary.strongest, c.pair.left.cols);
  if (!cylinder) s.options.max_edge_angle_deg = c.opt.box_edge_angle_deg;
  s.options.region_weight = c.opt.region_weight;
  s.views = {FitView{&c.in.left_camera, &c.grad_left}, FitView{&c.in.right_camera, &c.grad_right}};
  if (c.opt.keep_to_marks) BoundByMarks(c.marks, c.pair, c.depth0, cylinder, c.opt, &s.views);
  HideBehindKnown(c.in_front, &s.views);
  RaisedPipeStarts raised;  // tried when the others fit poorly
  raised.with_upper_part = asked;
  std::vector<Eigen::VectorXd> box_if_poor;  // tried when the world-aligned box fits poorly
  std::vector<Eigen::VectorXd> starts =
      cylinder
          ? CylinderStarts(c.pair, c.boundary.pixels, c.depth0, c.search, c.opt, &c.grad_left,
                           &raised)
          : BoxStarts(c.in.left_camera, c.boundary.pixels, c.depth0, &c.grad_left, &box_if_poor);
  if (cylinder)  // each start also stretched to fill the marks along its axis
    for (auto* list : {&starts, &raised.upper_limb, &raised.upper_part, &raised.crossing})
      AddStretched(c.marks, c.in.left_camera, c.opt, list);
  const Eigen::VectorXd& x0 = starts[0];
  spdlog::debug("locate: {} from {} starts, the first [{}]", cylinder ? "cylinder" : "box",
                starts.size(),
                FormatFixed(x0[0]) + " " + FormatFixed(x0[1]) + " " + FormatFixed(x0[2]) + " / " +
                    FormatFixed(x0[3]) + " " + FormatFixed(x0[4]) + " " + FormatFixed(x0[5]) +
                    " / " + FormatFixed(x0[6]));
  s.fit = cylinder ? FitCylinder(starts, s.views, s.options, c.opt, c.plausible)
                   : FitBox(starts, s.views, s.options, c.opt, c.plausible, box_if_poor);
  std::vector<Eigen::VectorXd> raised_starts = std::move(raised.upper_limb);
  raised_starts.insert(raised_starts.end(), raised.upper_part.begin(), raised.upper_part.end());
  TryRaisedPipe(raised_starts, s.views, s.options, c.opt, c.plausible, &s.fit);
  // A pipe leaning across its block (leaning_pipe_score). Not for the rival pipe fitted
  // against a block asked for: it explained the blocks' outlines as well as they did, and
  // refused them.
  if (cylinder && asked &&
      (!s.fit.ok ||
       FitScore(s.fit, ScoreResidualScale(c.opt, c.pair.left.cols)) > c.opt.leaning_pipe_score))
    TryRaisedPipe(raised.crossing, s.views, s.options, c.opt, c.plausible, &s.fit, true);
  if (cylinder && asked) TryBesideLimb(c.in.marks, s.views, s.options, c.opt, c.plausible, &s.fit);
  if (!cylinder) {
    LowerToSides(c, s.views, s.options, &s.fit, &s.open_lowered);
    LowerByShares(c, s.views, s.options, &s.fit, &s.open_lowered);
    TurnToCrease(c, s.views, s.options, &s.fit);
  }
  // A rival block is left where it was fitted: stood on the floor, it took the outline of a
  // pipe lying on the table (fresh seeds, level pipes at 1920x1080, seed 7006 lying_0, found
  // right to 0.002 in) and refused it.
  if (cylinder || asked) StandOnFloor(c, cylinder, s.views, s.options, &s.fit);
  if (cylinder) {
    EndsFromLimbs(s.views, s.options, c.opt, &s.fit);
    FootOnFloor(s.views, c.opt, &s.fit);
  }
  return s;
}

}  // namespace

KnownShape KnownFromResult(const LocateResult& result, std::string name) {
  KnownShape k;
  k.name = std::move(name);
  k.type = result.type;
  k.params.resize(7);
  if (result.type == SolidType::kCylinder) {
    const CylinderResult& c = result.cylinder;
    k.params << c.center - 0.5 * c.height * c.axis, c.center + 0.5 * c.height * c.axis, c.radius;
    k.sigma = c.center_sigma.z() + c.radius_sigma;
  } else {
    const BoxResult& b = result.box;
    k.params << b.center, b.size, b.yaw_deg * M_PI / 180;
    k.sigma = b.center_sigma.z() + 0.5 * b.size_sigma.z();
  }
  return k;
}

const char* FailureName(Failure f) {
  switch (f) {
    case Failure::kNone:
      return "none";
    case Failure::kBadInput:
      return "bad_input";
    case Failure::kMarksDegenerate:
      return "marks_degenerate";
    case Failure::kMarksBehindCamera:
      return "marks_behind_camera";
    case Failure::kMarksOutsideImage:
      return "marks_outside_image";
    case Failure::kNoEdgeNearMarks:
      return "no_edge_near_marks";
    case Failure::kEdgeCountMismatch:
      return "edge_count_mismatch";
    case Failure::kMatchOverThreshold:
      return "match_over_threshold";
    case Failure::kLeftRightInconsistent:
      return "left_right_inconsistent";
    case Failure::kFitFailed:
      return "fit_failed";
    case Failure::kOccluded:
      return "occluded";
    case Failure::kAlreadyModelled:
      return "already_modelled";
  }
  return "unknown";
}

// The result: the fitted solid's sizes, each checked as the images determine it, a box's
// texture, and the solid checked against the known ones.
static std::optional<StepFailure> ResultFromFit(const LocateInput& in, const FitOutcome& f,
                                                const cv::Rect& image_rect,
                                                const LocateOptions& opt, LocateResult* res) {
  if (res->type == SolidType::kCylinder) {
    res->cylinder = CylinderFromFit(f.params, f.covariance);
    if (res->cylinder.height < 1e-6 || res->cylinder.radius < 1e-6)
      return StepFailure{Failure::kFitFailed, "the fitted cylinder has no size"};
    if (auto failure = CheckCylinderWidth(res->cylinder, in.left_camera, opt)) return failure;
    if (auto failure = CheckCylinderLengthDetermined(res->cylinder, opt)) return failure;
  } else {
    res->box = BoxFromFit(f.params, f.covariance);
    if (res->box.size.minCoeff() < 1e-6)
      return StepFailure{Failure::kFitFailed, "the fitted box has no size"};
    ReachUpToKnown(in.known, opt, &res->box);
    if (auto failure = CheckBoxSizesDetermined(res->box, opt)) return failure;
    WidenForFitScore(res->fit_score, opt, &res->box);
    const StepResult<cv::Rect> rect = BoxTextureRect(f.params, in.left_camera, image_rect);
    if (!rect.ok()) return rect.failure();
    res->box.texture_rect = *rect;
    if (!rect->empty()) res->box.texture = LeftTexture(in, *rect);
  }
  return CheckNotKnown(*res, in.known, opt);
}

// Samples of each view's outline: in all, outside the image, with contrast, with an edge.
static void DebugOutlineSupport(const std::array<OutlineSupport, 2>& support) {
  spdlog::debug("locate: outline support left {}/{}/{}/{} right {}/{}/{}/{}", support[0].samples,
                support[0].outside, support[0].contrasted, support[0].edged, support[1].samples,
                support[1].outside, support[1].contrasted, support[1].edged);
}

// "The fitted outline explains the edges poorly", with the score and its bound.
static StepFailure ExplainsPoorly(double score, const LocateOptions& opt,
                                  const std::string& why = "") {
  return {Failure::kLeftRightInconsistent,
          "the fitted outline explains the edges poorly (score " + FormatFixed(score) + ", limit " +
              FormatFixed(opt.max_fit_score) + ")" +
              (why.empty() ? ": another object's edges, or the other type?" : why)};
}

// Fails when the fit scores over max_fit_score on the whole outline, unless a lying pipe
// (`lying_past_bound`, judged by the caller) or an upright one is let past it on the outline
// that should show an edge: an upright when all but its foot shows. A block that explained
// the edges only fitted lower, with a size nothing held (`open`), says so.
static std::optional<StepFailure> CheckFitScore(const LocateResult& res, bool upright,
                                                bool lying_past_bound,
                                                const std::array<OutlineSupport, 2>& support,
                                                const std::optional<OpenLowered>& open,
                                                const LocateOptions& opt) {
  if (res.fit_score <= opt.max_fit_score || lying_past_bound) return std::nullopt;
  if (upright && res.fit_score <= opt.max_shown_fit_score &&
      res.supported_fit_score <= opt.max_upright_supported_score && ShowsAllButFoot(support, opt))
    return std::nullopt;
  if (!open) return ExplainsPoorly(res.fit_score, opt);
  const char* axis_names[3] = {"width", "depth", "height"};
  return ExplainsPoorly(
      res.fit_score, opt,
      "; fitted lower, as under something resting on it, the box explains them (score " +
          FormatFixed(open->score) + "), but nothing there holds its " + axis_names[open->axis] +
          " (" + FormatFixed(open->size) + " +/- " + FormatFixed(open->sigma) + ")");
}

// One pass of the locator on the prepared images, with checked options; `left_empty` says
// whether it refused a fit that leaves part of the marks empty (CheckWithinMarks).
static LocateResult LocateOnce(const LocateInput& in, const StereoPair& pair,
                               const LocateOptions& opt, bool* left_empty) {
  LocateResult res;
  res.type = in.type;
  std::string in_front_names;  // of the known solids in front of part of the marks
  auto fail = [&](const StepFailure& f) { return Fail(res, f, in_front_names); };
  const cv::Rect image_rect(0, 0, pair.left.cols, pair.left.rows);

  // 1. Marks (3.6, 3.8).
  const StepResult<MarkedRegion> marks = MarkRegion(in);
  if (!marks.ok()) return fail(marks.failure());

  // 2. Boundary in the left image (3.8.1), without the edges of known solids in front.
  const std::vector<KnownInFront> in_front = KnownSolidsInFront(in, *marks, opt);
  in_front_names = NamesInFront(in_front, marks->hull);
  const int pad = RegionPad(opt);
  const Gradients grad_left(pair.left, GrowRect(cv::boundingRect(marks->hull), pad, image_rect),
                            opt.edge_sigma);
  const Boundary boundary = FindBoundary(
      grad_left, *marks, VisibleEdgeMask(in_front, in.left_edges, pair.left.size()), opt);
  res.boundary_pixels = static_cast<int>(boundary.pixels.size());
  if (const auto failure = CheckBoundary(boundary, *marks, opt)) return fail(*failure);

  // 3. Depth by SSD along the epipolar segment of the marks' depth range (3.6), triangulated
  // (3.7).
  const DepthSearch search = ObjectDepthSearch(boundary.pixels, marks->depth, opt);
  const StepResult<SsdMatch> first_match = MatchObject(pair, search, opt);
  if (!first_match.ok()) return fail(first_match.failure());
  const SsdMatch match =
      NarrowByRange(in, pair, search, boundary, marks->depth, *first_match, opt, &res.range);
  res.ssd_rms = match.rms;
  res.match_zncc = match.zncc;
  if (const auto failure = CheckMatch(match, opt)) return fail(*failure);
  const auto x_match = TriangulateMatch(pair, search, match);
  if (!x_match)
    return fail({Failure::kMatchOverThreshold, "the right-image match does not triangulate"});
  const double depth0 = in.left_camera.Depth(*x_match);
  const Gradients grad_right(pair.right, RightRegion(search, match, pad, image_rect),
                             opt.edge_sigma);

  // 4. Starting models from the left boundary at the matched depth (3.8.1, 3.8.2), then the
  // joint fit to both images. Of the starts' fits, one the marks bound snugly goes before any
  // that leaves part of them empty or runs beyond them, whatever its score.
  spdlog::debug("locate: marks depth {:.2f}, matched depth {:.2f}, ssd rms {:.1f}, {} boundary px",
                marks->depth, depth0, match.rms, boundary.pixels.size());
  const bool cylinder = in.type == SolidType::kCylinder;
  const PlausibleFn plausible = [&](const FitOutcome& o) {
    return !CheckWithinMarks(o.outline[0], *marks, in.left_camera, opt);
  };
  const FitContext context{in,        pair,       *marks,   boundary, search,   depth0,
                           grad_left, grad_right, in_front, opt,      plausible};
  SolidFit solid = FitSolid(cylinder, context, true);
  const FitOutcome& f = solid.fit;
  const FitOptions& fit = solid.options;
  const std::array<FitView, 2>& views = solid.views;
  spdlog::debug("locate: fit {} left {}/{} rms {:.3f}, right {}/{} rms {:.3f}, inner {} {}",
                f.ok ? "ok" : f.error, f.used[0], f.sampled[0], f.rms_px[0], f.used[1],
                f.sampled[1], f.rms_px[1], f.inner_used[0], f.inner_used[1]);
  if (in.want_trace) {
    for (const auto& p : marks->hull) res.trace.marks_left.emplace_back(p.x, p.y);
    res.trace.boundary = boundary.pixels;
    res.trace.outline = f.outline;
    res.trace.measured = f.measured;
    res.trace.inlier = f.inlier;
  }
  res.outline_samples = f.used[0] + f.used[1];
  res.rms_left_px = f.rms_px[0];
  res.rms_right_px = f.rms_px[1];
  if (!f.ok) return fail({Failure::kFitFailed, "model fit: " + f.error});
  // How a pipe's side shades: the fitted one's; for a box, its rival's (below).
  SideShape side = cylinder ? ClassifySide(pair, f.params, views, opt) : SideShape::kUnmeasured;
  // 5. Consistency between the views, on the parts of the outline that should show an edge.
  // Per side too for an upright pipe (CheckLimbsAgree, ShowsAllButFoot), the only fit that
  // uses it.
  const auto measure_support = [&](const FitOutcome& o,
                                   bool per_side) -> std::array<OutlineSupport, 2> {
    return {
        MeasureOutlineSupport(o.outline[0], pair.left, grad_left, fit, views[0].hidden, per_side),
        MeasureOutlineSupport(o.outline[1], pair.right, grad_right, fit, views[1].hidden,
                              per_side)};
  };
  const bool upright = cylinder && UprightPipe(f.params, opt);
  const std::array<OutlineSupport, 2> support = measure_support(f, upright);
  const double score_scale = ScoreResidualScale(opt, pair.left.cols);
  res.fit_score = FitScore(f, score_scale);
  res.supported_fit_score = SupportedFitScore(f, support, score_scale);
  DebugOutlineSupport(support);
  if (const auto failure = CheckOutlineVisible(support, opt)) return fail(*failure);
  if (const auto failure = CheckWithinMarks(f.outline[0], *marks, in.left_camera, opt, left_empty))
    return fail(*failure);
  if (const auto failure = CheckBothViews(f, opt, &support)) return fail(*failure);
  if (upright)
    if (const auto failure = CheckLimbsAgree(support, opt)) return fail(*failure);
  const bool lying_past_bound = res.fit_score > opt.max_fit_score && cylinder &&
                                LyingPipe(f.params, opt) &&
                                res.fit_score <= opt.max_lying_fit_score &&
                                res.supported_fit_score <= opt.max_lying_supported_score;
  if (const auto failure =
          CheckFitScore(res, upright, lying_past_bound, support, solid.open_lowered, opt))
    return fail(*failure);

  // The other type.
  if (WantOtherType(cylinder, f, side, opt)) {
    const FitOutcome other = FitSolid(!cylinder, context, false).fit;
    if (!cylinder && other.ok) side = ClassifySide(pair, other.params, views, opt);
    spdlog::debug("locate: the other type scores {:.3f} against {:.3f}", FitScore(other),
                  FitScore(f));
    res.other_type_fit_score = FitScore(other, score_scale);
    res.other_type_supported_fit_score =
        other.ok ? SupportedFitScore(other, measure_support(other, false), score_scale)
                 : res.other_type_fit_score;
    if (const auto failure =
            CheckOtherType(cylinder, f, other, other.ok && plausible(other), side,
                           {res.fit_score, res.other_type_fit_score, res.supported_fit_score,
                            res.other_type_supported_fit_score},
                           opt))
      return fail(*failure);
    if (lying_past_bound && other.ok &&
        res.other_type_supported_fit_score <
            opt.box_over_cylinder * res.supported_fit_score)  // a block better even there
      return fail(ExplainsPoorly(res.fit_score, opt));
  }

  if (!cylinder) RefineBoxForFaces(pair, views, fit, opt, &solid.fit);
  if (const auto failure = ResultFromFit(in, f, image_rect, opt, &res)) return fail(*failure);
  if (cylinder) RefineLimbsForShading(pair, views, fit, opt, f, &res.cylinder);
  if (in.range) CheckRange(in, opt, f.params, &res.range);
  res.found = true;
  return res;
}

// A refusal is tried again with a lower bar for edges, each pass's answer kept only when it
// finds the object (else the first refusal stands, with its reason). A fit that left the marks
// empty: the edges' strength taken at retry_edge_quantile, then for a block the gradient floor
// at the image's noise. A pipe whose outline the edges explained poorly, or not in both views
// (FAILURE_LEFT_RIGHT_INCONSISTENT): the floor at the noise, the rival box held against it
// outright (other_type_outright). The images are prepared once for every pass.
LocateResult Locate(const LocateInput& in, const LocateOptions& opt) {
  const auto start = Clock::now();
  const auto timed = [&](LocateResult r) {
    r.elapsed_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return r;
  };
  LocateResult refused;
  refused.type = in.type;
  if (std::string e; !opt.Check(&e))
    return timed(Fail(refused, {Failure::kBadInput, "options: " + e}, ""));
  const StepResult<StereoPair> pair = PrepareImages(in);
  if (!pair.ok()) return timed(Fail(refused, pair.failure(), ""));
  bool left_empty = false;
  LocateResult first = LocateOnce(in, *pair, opt, &left_empty);
  if (first.found) return timed(first);
  const auto at_noise = [&](LocateOptions o, const char* what) {
    LocateResult r;
    if (const auto low = NoiseFloorOptions(in, *pair, std::move(o))) {
      r = LocateOnce(in, *pair, *low, nullptr);
      spdlog::debug("locate: {} again with the gradient floor at the image's noise: {}", what,
                    r.found ? "found" : r.detail);
    }
    return r;
  };
  if (!left_empty) {
    if (in.type == SolidType::kCylinder && first.reason == Failure::kLeftRightInconsistent) {
      LocateOptions pipe = opt;
      pipe.other_type_score = 0;  // the rival box always fitted, and held against it outright
      pipe.other_type_outright = true;
      if (LocateResult r = at_noise(pipe, "a pipe"); r.found) return timed(std::move(r));
    }
    return timed(first);
  }
  LocateOptions again = opt;
  if (opt.retry_edge_quantile > 0 && opt.retry_edge_quantile < opt.edge_strength_quantile) {
    again.edge_strength_quantile = opt.retry_edge_quantile;
    LocateResult second = LocateOnce(in, *pair, again, nullptr);
    spdlog::debug("locate: again with the edges' strength at their {:.2f} quantile: {}",
                  opt.retry_edge_quantile, second.found ? "found" : second.detail);
    if (second.found) return timed(std::move(second));
  }
  if (in.type == SolidType::kBox)
    if (LocateResult r = at_noise(again, "a block"); r.found) return timed(std::move(r));
  return timed(std::move(first));
}

}  // namespace igms::object
