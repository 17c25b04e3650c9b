// Steps 4-5 of the locator (locate_steps.h): the fit, the check of both views, and the result
// from the fit. The starting models are in locate_start_steps.cpp.
#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "object_server/locate_steps.h"
#include "object_server/ranger.h"
#include "object_server/solid_models.h"

namespace igms::object {
namespace {

// Propagates the parameter covariance through f by a numeric Jacobian; returns the
// standard deviations of f's outputs.
Eigen::VectorXd Sigmas(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                       const Eigen::VectorXd& x, const Eigen::MatrixXd& cov) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), x.size());
  for (int k = 0; k < x.size(); ++k) {
    Eigen::VectorXd xp = x;
    xp[k] += 1e-6;
    J.col(k) = (f(xp) - f0) / 1e-6;
  }
  return (J * cov * J.transpose()).diagonal().cwiseMax(0).cwiseSqrt();
}

// A box fit that kept a depth: one that flattened the box explained nothing (the turned box's
// faces drawn as one). A failed fit has no parameters to look at.
bool IsSolid(const FitOutcome& o) {
  if (!o.ok || o.params.size() < 6) return false;
  const Eigen::Vector3d size = o.params.segment<3>(3).cwiseAbs();
  return size.minCoeff() > 0.1 * size.maxCoeff();
}

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
// within kLimbGapPx, and not out of `region` (when given). The farther-reaching limb sets each
// end. nullopt when a limb has no edge at the middle.
std::optional<std::pair<double, double>> LimbExtent(const Gradients& gradients,
                                                    const std::vector<Eigen::Vector2d>& region,
                                                    const Eigen::Vector2d& q0,
                                                    const Eigen::Vector2d& dir, double length,
                                                    double radius_px, double min_gradient) {
  constexpr double kLimbGapPx = 4.0, kLimbBandPx = 2.0;
  const Eigen::Vector2d n(-dir.y(), dir.x());
  const auto edge_at = [&](double s, double side) {
    const Eigen::Vector2d on = q0 + s * dir + side * radius_px * n;
    if (region.size() >= 3 && SignedDistance(region, on) > 0) return false;
    for (double o = -kLimbBandPx; o <= kLimbBandPx; o += 0.5)
      if (std::abs(gradients.At(on + o * n).dot(n)) >= min_gradient) return true;
    return false;
  };
  double lo = 1e18, hi = -1e18;
  for (const double side : {-1.0, 1.0}) {
    const double mid = 0.5 * length;
    if (!edge_at(mid, side) && !edge_at(mid - 1, side) && !edge_at(mid + 1, side))
      return std::nullopt;
    for (const double step : {-1.0, 1.0}) {
      double last = mid;
      for (double s = mid + step; std::abs(s - last) <= kLimbGapPx; s += step) {
        if (s < -length || s > 2 * length) break;
        if (edge_at(s, side)) last = s;
      }
      if (step < 0)
        lo = std::min(lo, last);
      else
        hi = std::max(hi, last);
    }
  }
  return std::make_pair(lo, hi);
}

}  // namespace

FitOptions FitSettings(const LocateOptions& options, double strongest) {
  FitOptions fit;
  fit.search_px = options.search_px;
  fit.min_gradient = std::max(options.min_edge_gradient, 0.25 * strongest);
  fit.edge_blur_px = std::hypot(options.edge_sigma, options.camera_blur_px);
  fit.outer_iterations = options.outer_iterations;
  fit.inner_iterations = options.inner_iterations;
  fit.runner_up_above = options.poor_fit_score;
  return fit;
}

double FitScore(const FitOutcome& fit, double residual_scale) {
  const int sampled = fit.sampled[0] + fit.sampled[1];
  const double miss = sampled ? 1.0 - double(fit.used[0] + fit.used[1]) / sampled : 1.0;
  return fit.ok ? residual_scale * (fit.rms_px[0] + fit.rms_px[1]) + 2.0 * miss : 1e18;
}

double SupportedFitScore(const FitOutcome& fit, const std::array<OutlineSupport, 2>& support,
                         double residual_scale) {
  const int contrasted = support[0].contrasted + support[1].contrasted;
  if (!fit.ok || contrasted == 0) return FitScore(fit, residual_scale);
  const double miss = 1.0 - double(support[0].edged + support[1].edged) / contrasted;
  return residual_scale * (fit.rms_px[0] + fit.rms_px[1]) + 2.0 * miss;
}

double ScoreResidualScale(const LocateOptions& options, int image_width) {
  if (image_width <= 0) return 1.0;
  return std::pow(options.score_reference_width_px / image_width, options.score_width_power);
}

bool BetterFit(const FitOutcome& a, const FitOutcome& b, const PlausibleFn& plausible) {
  if (plausible && a.ok && b.ok) {
    const bool pa = plausible(a), pb = plausible(b);
    if (pa != pb) return pa;
  }
  return FitScore(a) < FitScore(b);
}

FitOutcome FitFromStarts(const OutlineFn& outline, const InnerEdgesFn& inner,
                         const std::vector<Eigen::VectorXd>& starts,
                         const std::array<FitView, 2>& views, const FitOptions& fit,
                         const PlausibleFn& plausible) {
  FitOptions first = fit;
  first.step = Eigen::VectorXd::Constant(starts[0].size(), 1e-4);
  first.outer_iterations =
      starts.size() == 1 ? fit.outer_iterations : std::min(2, fit.outer_iterations);
  // The runner-up of the short fits also runs to the end when the best ends poorly: a short
  // fit's score ranks the starts only roughly, and the runner-up may end better.
  FitOutcome best = FitSilhouette(outline, starts[0], views, first, inner), second;
  for (size_t i = 1; i < starts.size(); ++i) {
    FitOutcome g = FitSilhouette(outline, starts[i], views, first, inner);
    spdlog::debug("locate: another start: score {:.3f} against {:.3f}", FitScore(g),
                  FitScore(best));
    if (BetterFit(g, best, plausible)) {
      second = std::move(best);
      best = std::move(g);
    } else if (!second.ok || BetterFit(g, second, plausible)) {
      second = std::move(g);
    }
  }
  if (first.outer_iterations < fit.outer_iterations) {
    FitOptions rest = first;
    rest.outer_iterations = fit.outer_iterations;
    rest.first_outer = first.outer_iterations;
    if (best.ok) best = FitSilhouette(outline, best.params, views, rest, inner);
    if (second.ok && (!best.ok || FitScore(best) > fit.runner_up_above)) {
      FitOutcome g = FitSilhouette(outline, second.params, views, rest, inner);
      spdlog::debug("locate: the runner-up ends at {:.3f} against {:.3f}", FitScore(g),
                    FitScore(best));
      if (BetterFit(g, best, plausible)) best = std::move(g);
    }
  }
  return best;
}

FitOutcome FitCylinder(const std::vector<Eigen::VectorXd>& starts,
                       const std::array<FitView, 2>& views, const FitOptions& fit,
                       const LocateOptions& options, const PlausibleFn& plausible) {
  InnerEdgesFn inner;
  if (options.cylinder_inner_edges) inner = CylinderInnerEdges;
  return FitFromStarts(CylinderOutline, inner, starts, views, fit, plausible);
}

FitOutcome FitBox(const std::vector<Eigen::VectorXd>& starts, const std::array<FitView, 2>& views,
                  const FitOptions& fit, const LocateOptions& options,
                  const PlausibleFn& plausible) {
  const OutlineFn outline = BoxOutline;
  InnerEdgesFn inner;
  if (options.box_inner_edges) inner = BoxInnerEdges;
  // World-aligned: the first six parameters, the yaw held at 0.
  auto aligned = [](const Eigen::VectorXd& p) {
    Eigen::VectorXd q(7);
    q << p, 0.0;
    return q;
  };
  std::vector<Eigen::VectorXd> starts6, yawed;
  starts6.reserve(starts.size());
  for (const auto& st : starts) {
    if (st[6] == 0.0)
      starts6.push_back(st.head<6>());
    else
      yawed.push_back(st);
  }
  InnerEdgesFn inner6;
  if (inner)
    inner6 = [&](const Eigen::VectorXd& p, const Eigen::Vector3d& c) {
      return inner(aligned(p), c);
    };
  FitOutcome f = FitFromStarts([&](const Eigen::VectorXd& p) { return outline(aligned(p)); },
                               inner6, starts6, views, fit, plausible);
  if (f.ok) {
    f.params = aligned(f.params);
    Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(7, 7);
    cov.topLeftCorner<6, 6>() = f.covariance;
    f.covariance = cov;
  }
  const bool poor = !IsSolid(f) || 0.5 * (f.rms_px[0] + f.rms_px[1]) > options.box_turn_rms_px;
  if (!poor && yawed.empty()) return f;
  // A poor aligned fit is turned both ways by up to 36 degrees; a good one only to the yaws
  // the edges show, beside the starts at those yaws.
  std::vector<Eigen::VectorXd> turned = yawed;
  const Eigen::VectorXd from = IsSolid(f) ? f.params : starts[0];
  const auto turn_to = [&](double yaw) {
    Eigen::VectorXd st = from;
    st[6] = yaw;
    turned.push_back(st);
  };
  if (poor)
    for (const double yaw_deg : {-36.0, -18.0, 0.0, 18.0, 36.0}) turn_to(yaw_deg * M_PI / 180);
  else
    for (const auto& st : yawed)
      if (std::none_of(turned.begin() + static_cast<long>(yawed.size()), turned.end(),
                       [&](const Eigen::VectorXd& t) { return t[6] == st[6]; }))
        turn_to(st[6]);
  FitOutcome fo = FitFromStarts(outline, inner, turned, views, fit, plausible);
  spdlog::debug("locate: turned box: score {:.3f} against aligned {:.3f}", FitScore(fo),
                FitScore(f));
  if (plausible && f.ok && fo.ok && IsSolid(fo) && plausible(fo) != plausible(f))
    return plausible(fo) ? fo : f;
  if (!f.ok || (IsSolid(fo) && (!IsSolid(f) || FitScore(fo) < 0.8 * FitScore(f)))) return fo;
  return f;
}

OutlineSupport MeasureOutlineSupport(const std::vector<Eigen::Vector2d>& outline,
                                     const cv::Mat& image, const Gradients& gradients,
                                     const FitOptions& fit,
                                     const std::vector<std::vector<Eigen::Vector2d>>& hidden) {
  OutlineSupport out;
  const int n = static_cast<int>(outline.size());
  if (n < 3 || image.empty()) return out;
  double area = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = outline[i];
    const Eigen::Vector2d& b = outline[(i + 1) % n];
    area += a.x() * b.y() - a.y() * b.x();
  }
  const double orient = area >= 0 ? 1.0 : -1.0;
  // The image's noise near the outline: the median absolute difference of horizontal
  // neighbours (edges are too few to move the median), over sqrt(2) for the difference.
  cv::Rect box = cv::boundingRect(std::vector<cv::Point2f>(
      1, cv::Point2f(static_cast<float>(outline[0].x()), static_cast<float>(outline[0].y()))));
  for (const auto& p : outline)
    box |= cv::Rect(static_cast<int>(std::floor(p.x())), static_cast<int>(std::floor(p.y())), 2, 2);
  box = GrowRect(box, 6, cv::Rect(0, 0, image.cols, image.rows));
  std::vector<int> diffs;
  for (int y = box.y; y < box.y + box.height; ++y) {
    const uint8_t* row = image.ptr<uint8_t>(y);
    for (int x = box.x; x + 1 < box.x + box.width; ++x)
      diffs.push_back(std::abs(row[x + 1] - row[x]));
  }
  if (!diffs.empty()) {
    std::nth_element(diffs.begin(), diffs.begin() + static_cast<std::ptrdiff_t>(diffs.size() / 2),
                     diffs.end());
    out.noise_sigma = 1.4826 * diffs[diffs.size() / 2] / std::sqrt(2.0);
  }
  auto grey = [&](const Eigen::Vector2d& p) {
    const double x = std::clamp(p.x(), 0.0, image.cols - 1.001);
    const double y = std::clamp(p.y(), 0.0, image.rows - 1.001);
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const double fx = x - x0, fy = y - y0;
    const auto at = [&](int yy, int xx) { return static_cast<double>(image.at<uint8_t>(yy, xx)); };
    return (1 - fy) * ((1 - fx) * at(y0, x0) + fx * at(y0, x0 + 1)) +
           fy * ((1 - fx) * at(y0 + 1, x0) + fx * at(y0 + 1, x0 + 1));
  };
  // A step of c grey levels blurred by edge_blur_px peaks at c / (sqrt(2 pi) blur) per pixel:
  // the detector (min_gradient) sees steps of at least this. The means either side are of 6
  // samples each, so their difference has noise sigma * sqrt(2 / 6).
  const double blur = std::max(0.8, fit.edge_blur_px);
  const double min_step = std::max({1.2 * std::sqrt(2 * M_PI) * blur * fit.min_gradient,
                                    4.0 * out.noise_sigma * std::sqrt(2.0 / 6.0), 4.0});
  // Sharp corners (a box's, a pipe's ends seen side on): the edge there is blurred round, so
  // samples within 2 px of a vertex turning by over 30 degrees are left out.
  std::vector<bool> sharp(n, false);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d in = outline[i] - outline[(i + n - 1) % n];
    const Eigen::Vector2d on = outline[(i + 1) % n] - outline[i];
    if (in.norm() > 1e-9 && on.norm() > 1e-9)
      sharp[i] = in.normalized().dot(on.normalized()) < std::cos(30 * M_PI / 180);
  }
  auto inside = [&](const Eigen::Vector2d& q) {
    return q.x() >= 0 && q.y() >= 0 && q.x() <= image.cols - 1 && q.y() <= image.rows - 1;
  };
  double carry = 0;  // arc length from the last sample
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = outline[i];
    const Eigen::Vector2d& b = outline[(i + 1) % n];
    const double len = (b - a).norm();
    if (len < 1e-9) continue;
    const Eigen::Vector2d dir = (b - a) / len;
    const Eigen::Vector2d normal = orient * Eigen::Vector2d(dir.y(), -dir.x());
    double t = 1.0 - carry;
    for (; t <= len; t += 1.0) {
      if ((sharp[i] && t < 2.0) || (sharp[(i + 1) % n] && t > len - 2.0)) continue;
      const Eigen::Vector2d p = a + t * dir;
      ++out.samples;
      if (!inside(p + 4 * normal) || !inside(p - 4 * normal)) {
        ++out.outside;
        continue;
      }
      if (InsideAny(hidden, p)) {
        ++out.hidden;
        continue;
      }
      double in_sum = 0, out_sum = 0;
      for (const double d : {2.5, 3.5})
        for (const double w : {-1.0, 0.0, 1.0}) {
          in_sum += grey(p - d * normal + w * dir);
          out_sum += grey(p + d * normal + w * dir);
        }
      if (std::abs(in_sum - out_sum) / 6 < min_step) continue;
      ++out.contrasted;
      double s;
      if (EdgeAlongNormal(gradients, p, normal, 2.5, fit.min_gradient, &s) && std::abs(s) <= 1.5)
        ++out.edged;
    }
    carry = len - (t - 1.0);
  }
  return out;
}

std::optional<StepFailure> CheckWithinMarks(const std::vector<Eigen::Vector2d>& left_outline,
                                            const MarkedRegion& marks,
                                            const geometry::ProjectiveCamera& left_camera,
                                            const LocateOptions& options) {
  if (left_outline.empty() || marks.hull.empty()) return std::nullopt;
  Eigen::Vector2d lo(1e18, 1e18), hi(-1e18, -1e18), mlo = lo, mhi = hi;
  for (const auto& p : left_outline) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  for (const auto& p : marks.hull) {
    mlo = mlo.cwiseMin(Eigen::Vector2d(p.x, p.y));
    mhi = mhi.cwiseMax(Eigen::Vector2d(p.x, p.y));
  }
  const Eigen::Vector2d c = 0.5 * (mlo + mhi);
  // World units per pixel at the marks' depth.
  const double unit = (PointOnPixelRay(left_camera, c + Eigen::Vector2d(1, 0), marks.depth) -
                       PointOnPixelRay(left_camera, c, marks.depth))
                          .norm();
  const double max_gap_px = options.max_mark_gap / std::max(1e-9, unit) + 2;
  const std::array<double, 4> gap = {lo.x() - mlo.x(), lo.y() - mlo.y(), mhi.x() - hi.x(),
                                     mhi.y() - hi.y()};
  const std::array<const char*, 4> side = {"left", "top", "right", "bottom"};
  for (int k = 0; k < 4; ++k) {
    if (gap[k] > max_gap_px)
      return StepFailure{Failure::kFitFailed, "the fitted model leaves " +
                                                  FormatFixed(gap[k] * unit, 1) +
                                                  " of the marked region empty on its " + side[k] +
                                                  ": it fits part of the object, or another one"};
    if (-gap[k] > options.max_beyond_marks_px)
      return StepFailure{Failure::kFitFailed, "the fitted model runs " + FormatFixed(-gap[k], 0) +
                                                  " px beyond the marks on their " + side[k] +
                                                  ": it takes in a neighbour's edges"};
  }
  return std::nullopt;
}

std::optional<StepFailure> CheckOutlineVisible(const std::array<OutlineSupport, 2>& support,
                                               const LocateOptions& options) {
  for (int v = 0; v < 2; ++v) {
    const OutlineSupport& s = support[v];
    const std::string name = v == 0 ? "left" : "right";
    if (s.samples == 0) continue;
    const double outside = double(s.outside) / s.samples;
    if (outside > options.max_outside_share)
      return StepFailure{Failure::kOccluded, FormatFixed(100 * outside, 0) +
                                                 "% of the fitted outline lies beyond the " + name +
                                                 " image's edge: only part of the "
                                                 "object is in view"};
    const int inside = s.samples - s.outside;
    const double contrasted = inside ? double(s.contrasted) / inside : 0.0;
    if (contrasted < options.min_contrast_share)
      return StepFailure{Failure::kOccluded,
                         "only " + FormatFixed(100 * contrasted, 0) +
                             "% of the fitted outline stands out from what lies behind it in "
                             "the " +
                             name +
                             " image: an object in front hides the rest, or it has the shade "
                             "of its background"};
  }
  return std::nullopt;
}

std::optional<StepFailure> CheckBothViews(const FitOutcome& fit, const LocateOptions& options,
                                          const std::array<OutlineSupport, 2>* support) {
  for (int v = 0; v < 2; ++v) {
    const char* name = v == 0 ? "left" : "right";
    double share = fit.sampled[v] ? double(fit.used[v]) / fit.sampled[v] : 0.0;
    if (support && (*support)[v].contrasted > 0)
      share = double((*support)[v].edged) / (*support)[v].contrasted;
    if (share < options.min_inlier_share)
      return StepFailure{Failure::kLeftRightInconsistent,
                         std::string("only ") + FormatFixed(100 * share, 0) +
                             "% of the fitted outline has an edge in the " + name +
                             " image: the object is not the same in both views"};
    if (fit.rms_px[v] > options.max_rms_px)
      return StepFailure{Failure::kLeftRightInconsistent,
                         std::string("the fitted outline misses the ") + name +
                             " image's edges by " + FormatFixed(fit.rms_px[v]) + " px RMS (limit " +
                             FormatFixed(options.max_rms_px) + ")"};
  }
  return std::nullopt;
}

std::optional<StepFailure> CheckOtherType(bool cylinder, const FitOutcome& f,
                                          const FitOutcome& other, bool other_within_marks,
                                          const LocateOptions& opt) {
  if (!other.ok) return std::nullopt;
  if (cylinder && other_within_marks && !CheckBothViews(other, opt) &&
      opt.other_type_ratio * FitScore(other) < FitScore(f))
    return StepFailure{Failure::kFitFailed, "a box explains the outline much better (score " +
                                                FormatFixed(FitScore(other)) + " against " +
                                                FormatFixed(FitScore(f)) +
                                                "): is the object a box?"};
  if (!cylinder && FitScore(f) > opt.box_over_cylinder * FitScore(other))
    return StepFailure{Failure::kFitFailed,
                       "a cylinder explains the outline about as well as a box (score " +
                           FormatFixed(FitScore(other)) + " against " + FormatFixed(FitScore(f)) +
                           "): is the object a cylinder?"};
  return std::nullopt;
}

CylinderResult CylinderFromFit(const Eigen::VectorXd& params, const Eigen::MatrixXd& covariance) {
  // Centre, radius and height, with their deviations.
  auto outputs = [](const Eigen::VectorXd& p) {
    Eigen::VectorXd o(5);
    o.head<3>() = 0.5 * (p.segment<3>(0) + p.segment<3>(3));
    o[3] = std::abs(p[6]);
    o[4] = (p.segment<3>(3) - p.segment<3>(0)).norm();
    return o;
  };
  const Eigen::VectorXd o = outputs(params), s = Sigmas(outputs, params, covariance);
  CylinderResult c;
  c.center = o.head<3>();
  c.radius = o[3];
  c.height = o[4];
  c.center_sigma = s.head<3>();
  c.radius_sigma = s[3];
  c.height_sigma = s[4];
  if (c.height < 1e-6 || c.radius < 1e-6) return c;
  Eigen::Vector3d axis = params.segment<3>(3) - params.segment<3>(0);
  axis.normalize();
  // A stable sign: pointing up, or along +x for a level axis.
  if (axis.z() < -1e-9 || (std::abs(axis.z()) <= 1e-9 && axis.x() < 0)) axis = -axis;
  c.axis = axis;
  return c;
}

BoxResult BoxFromFit(const Eigen::VectorXd& params, const Eigen::MatrixXd& covariance) {
  // Centre, size, yaw and the world-axis-aligned extent, with their deviations.
  auto outputs = [](const Eigen::VectorXd& p) {
    const Eigen::VectorXd q = CanonicalBox(p);
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e18), hi = -lo;
    for (const auto& c : BoxOutline(q)) {
      lo = lo.cwiseMin(c);
      hi = hi.cwiseMax(c);
    }
    Eigen::VectorXd o(13);
    o << q.head<7>(), lo, hi;
    return o;
  };
  const Eigen::VectorXd o = outputs(params), sd = Sigmas(outputs, params, covariance);
  BoxResult b;
  b.center = o.head<3>();
  b.size = o.segment<3>(3);
  b.yaw_deg = o[6] * 180 / M_PI;
  b.rotation = BoxRotation(o[6]);
  b.center_sigma = sd.head<3>();
  b.size_sigma = sd.segment<3>(3);
  b.yaw_sigma_deg = sd[6] * 180 / M_PI;
  b.min = o.segment<3>(7);
  b.max = o.segment<3>(10);
  b.min_sigma = sd.segment<3>(7);
  b.max_sigma = sd.segment<3>(10);
  return b;
}

void ReachUpToKnown(const std::vector<KnownShape>& known, const LocateOptions& opt,
                    BoxResult* box) {
  if (!(box->size_sigma.z() > opt.max_box_size_sigma)) return;
  const double bottom = box->min.z();
  const Eigen::Vector2d c = box->center.head<2>();
  const double reach = 0.5 * box->size.head<2>().norm();
  std::optional<double> top;
  double top_sigma = 0;
  for (const KnownShape& k : known) {
    if (k.type != SolidType::kCylinder || k.params.size() != 7 || !k.params.allFinite()) continue;
    const Eigen::Vector3d p0 = k.params.head<3>(), p1 = k.params.segment<3>(3);
    const double len = (p1 - p0).norm(), r = k.params[6];
    if (len < 1e-9) continue;
    const Eigen::Vector3d a = (p1 - p0) / len;
    const double h2 = a.head<2>().squaredNorm();
    // Along the axis to above the block's centre (an upright pipe: its lower end).
    const double t =
        h2 > 1e-12 ? std::clamp((c - p0.head<2>()).dot(a.head<2>()) / h2, 0.0, len) : 0.0;
    const Eigen::Vector3d on = p0 + t * a;
    if ((on.head<2>() - c).norm() > reach) continue;
    const double underside = on.z() - r * std::sqrt(std::max(0.0, 1 - a.z() * a.z()));
    if (underside > bottom + 0.1 && (!top || underside < *top)) {
      top = underside;
      top_sigma = k.sigma;
    }
  }
  if (!top) return;
  box->size.z() = *top - bottom;
  box->center.z() = 0.5 * (*top + bottom);
  box->max.z() = *top;
  box->max_sigma.z() = top_sigma;
  box->size_sigma.z() = std::hypot(box->min_sigma.z(), top_sigma);
  box->center_sigma.z() = 0.5 * box->size_sigma.z();
}

StepResult<cv::Rect> BoxTextureRect(const Eigen::VectorXd& params,
                                    const geometry::ProjectiveCamera& left_camera,
                                    const cv::Rect& image) {
  double u0 = 1e18, v0 = 1e18, u1 = -1e18, v1 = -1e18;
  for (const auto& p : BoxOutline(params)) {
    const auto px = left_camera.Project(p);
    if (!px)
      return StepFailure{Failure::kFitFailed,
                         "a corner of the fitted box does not project into the left image"};
    u0 = std::min(u0, px->x());
    v0 = std::min(v0, px->y());
    u1 = std::max(u1, px->x());
    v1 = std::max(v1, px->y());
  }
  return cv::Rect(
             cv::Point(static_cast<int>(std::floor(u0)), static_cast<int>(std::floor(v0))),
             cv::Point(static_cast<int>(std::ceil(u1)) + 1, static_cast<int>(std::ceil(v1)) + 1)) &
         image;
}

void CheckRange(const LocateInput& in, const LocateOptions& options, const Eigen::VectorXd& params,
                RangeCheck* check) {
  const Eigen::VectorXd& x = params;
  const double spacing = 0.05;
  std::vector<Eigen::Vector3d> surface =
      in.type == SolidType::kCylinder
          ? CylinderSurface(x.segment<3>(0), x.segment<3>(3), std::abs(x[6]), spacing)
          : BoxSurface(-0.5 * x.segment<3>(3).cwiseAbs(), 0.5 * x.segment<3>(3).cwiseAbs(),
                       spacing);
  if (in.type == SolidType::kBox) {  // from the box's own frame to the world
    const Eigen::Matrix3d R = BoxRotation(x[6]);
    for (auto& p : surface) p = x.head<3>() + R * p;
  }
  const RangerPose ranger{in.ranger_origin, in.ranger_axis.normalized()};
  const auto beam =
      RangesInBeam(surface, ranger, options.ranger_half_angle_deg * M_PI / 180, spacing);
  if (!beam) {
    check->agrees = false;
    check->detail = "the ranger's " + FormatFixed(2 * options.ranger_half_angle_deg, 0) +
                    "-degree beam does not reach the located object: the range " +
                    FormatFixed(check->measured) + " measured something else";
    return;
  }
  check->expected_min = beam->nearest;
  check->expected_max = beam->on_axis;
  const double acc = options.ranger_accuracy;
  if (check->measured < beam->nearest - acc) {
    check->agrees = false;
    check->detail = "the range " + FormatFixed(check->measured) + " is " +
                    FormatFixed(beam->nearest - check->measured) +
                    " shorter than the located object's nearest point in the beam (" +
                    FormatFixed(beam->nearest) +
                    "): something nearer is in the beam, or the model is wrong";
  } else if (check->measured > beam->on_axis + acc) {
    check->agrees = false;
    check->detail = "the range " + FormatFixed(check->measured) + " is " +
                    FormatFixed(check->measured - beam->on_axis) +
                    " beyond where the beam meets the located object (" +
                    FormatFixed(beam->on_axis) + "): the model is nearer than the ranger says";
  }
}

}  // namespace igms::object

namespace igms::object {

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
  constexpr int kBackgroundReachPx = 5;
  std::array<double, 2> unit{0, 0};
  std::array<std::optional<std::pair<double, double>>, 2> between;  // limbs' end, marks' exit
  for (int v = 0; v < 2; ++v) {
    const geometry::ProjectiveCamera& cam = *views[v].camera;
    const auto q0 = cam.Project(p0), q1 = cam.Project(p1);
    if (!q0 || !q1 || (*q1 - *q0).norm() < 8) return;
    const double length = (*q1 - *q0).norm();
    const Eigen::Vector2d dir = (*q1 - *q0) / length, n(-dir.y(), dir.x());
    double radius_px = 0;
    for (const auto& h : f->outline[v]) radius_px = std::max(radius_px, std::abs(n.dot(h - *q0)));
    const auto extent = LimbExtent(*views[v].gradients, views[v].region, *q0, dir, length,
                                   radius_px, fit.min_gradient);
    if (!extent) return;
    const auto t_lo = AxisParameterAt(cam, p0, p1, extent->first),
               t_hi = AxisParameterAt(cam, p0, p1, extent->second);
    if (!t_lo || !t_hi) return;
    // Where the background changes across the axis beside a limb's end (the table's far edge
    // behind an upright pipe), the limbs may stop because the pipe turns to the background's
    // shade there, not because it ends: that end stays as it was. The blur carries a limb's
    // edge a few pixels either side of the change.
    const auto background_changes = [&](double s_end) {
      for (const double side : {-1.0, 1.0})
        for (int k = -kBackgroundReachPx; k <= kBackgroundReachPx; ++k) {
          const Eigen::Vector2d q = *q0 + (s_end + k) * dir + side * (radius_px + 3) * n;
          if (std::abs(views[v].gradients->At(q).dot(dir)) > fit.min_gradient) return true;
        }
      return false;
    };
    // Limbs that run on to the marks' border say nothing of where the pipe ends (a
    // neighbour's edge in line with one can carry it there).
    const auto at_border = [&](double s_end, double out) {
      if (views[v].region.size() < 3) return false;
      for (const double side : {-1.0, 1.0}) {
        const Eigen::Vector2d past = *q0 + (s_end + 5 * out) * dir + side * radius_px * n;
        if (SignedDistance(views[v].region, past) > 0) return true;
      }
      return false;
    };
    const auto seen = [&](double s_end, double out, double t) {
      return background_changes(s_end) || at_border(s_end, out) ? kKeep : t;
    };
    reach[0].push_back(seen(extent->first, -1, *t_lo));
    reach[1].push_back(seen(extent->second, 1, *t_hi));
    unit[v] = len / length;
    // In the left image, where the limbs stop at a change of the background, the pipe ends
    // between there and where its axis leaves the marks.
    if (v == 0 && views[v].region.size() >= 3)
      for (int end = 0; end < 2; ++end) {
        const double out = end == 0 ? -1.0 : 1.0;
        const double s_end = end == 0 ? extent->first : extent->second;
        if (!background_changes(s_end) || at_border(s_end, out)) continue;
        double s = s_end;
        while (std::abs(s - s_end) < 4 * length &&
               SignedDistance(views[v].region, *q0 + (s + out) * dir) <= 0)
          s += out;
        const auto t_exit = AxisParameterAt(cam, p0, p1, s);
        if (t_exit) between[end] = {end == 0 ? *t_lo : *t_hi, *t_exit};
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
  const std::vector<Eigen::Vector3d> points = CylinderOutline(x);
  for (int v = 0; v < 2; ++v) {
    std::vector<Eigen::Vector2d> px_points;
    for (const auto& X : points)
      if (const auto q = views[v].camera->Project(X)) px_points.push_back(*q);
    f->outline[v] = ConvexHull(px_points);
  }
}

}  // namespace igms::object
