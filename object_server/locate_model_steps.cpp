// Steps 4-5 of the locator (locate_steps.h): the starting models, the fit, the check of both
// views, and the result from the fit.
#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <opencv2/imgproc.hpp>

#include "common/geometry/triangulation.h"
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

// The tilted start of a pipe lying towards the cameras (CylinderStarts): each end's patch
// matched into the right image on its own; nullopt when an end has no match.
std::optional<Eigen::VectorXd> TiltedCylinderStart(
    const StereoPair& pair, const DepthSearch& search, const Eigen::VectorXd& start,
    const Eigen::Vector2d& mid, const Eigen::Vector2d& along, double half_len, double half_width,
    double depth, double radius, const LocateOptions& options) {
  const geometry::ProjectiveCamera& left_camera = *pair.left_camera;
  const cv::Rect image_rect(0, 0, pair.left.cols, pair.left.rows);
  // The pipe's length across the view widens each end's depth range.
  const double lateral = (PointOnPixelRay(left_camera, mid + half_len * along, depth) -
                          PointOnPixelRay(left_camera, mid - half_len * along, depth))
                             .norm();
  Eigen::VectorXd tilted = start;
  for (int end = 0; end < 2; ++end) {
    const Eigen::Vector2d e = mid + (end == 0 ? -1.0 : 1.0) * (half_len - half_width) * along;
    const int side = static_cast<int>(std::ceil(2 * half_width)) + 8;
    const cv::Rect end_patch(static_cast<int>(std::lround(e.x())) - side / 2,
                             static_cast<int>(std::lround(e.y())) - side / 2, side, side);
    const auto ea = pair.right_camera->Project(
        PointOnPixelRay(left_camera, e, std::max(0.5 * search.near, search.near - lateral)));
    const auto eb =
        pair.right_camera->Project(PointOnPixelRay(left_camera, e, search.far + 2 * lateral));
    const Eigen::Vector2d pc(end_patch.x + 0.5 * (side - 1), end_patch.y + 0.5 * (side - 1));
    if (!ea || !eb) return std::nullopt;
    const SsdMatch m =
        MatchAlongSegment(pair.left, pair.right, end_patch & image_rect, *ea - pc, *eb - pc);
    const auto xe = m.ok && m.zncc >= options.min_match_zncc
                        ? TriangulateMidpoint(left_camera, pc, *pair.right_camera, pc + m.offset)
                        : std::nullopt;
    if (!xe) return std::nullopt;
    const Eigen::Vector2d tip =
        mid + (end == 0 ? -1.0 : 1.0) * (half_len - 0.5 * half_width) * along;
    tilted.segment<3>(3 * Eigen::Index{end}) =
        PointOnPixelRay(left_camera, tip, left_camera.Depth(*xe) + radius);
  }
  return tilted;
}

// A box's parameters from two opposite corners of its world-aligned extent and its yaw.
Eigen::VectorXd BoxParams(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double yaw) {
  Eigen::VectorXd v(7);
  v << 0.5 * (a + b), (b - a).cwiseAbs(), yaw;
  return v;
}

// A box fit that kept a depth: one that flattened the box explained nothing (the turned box's
// faces drawn as one). A failed fit has no parameters to look at.
bool IsSolid(const FitOutcome& o) {
  if (!o.ok || o.params.size() < 6) return false;
  const Eigen::Vector3d size = o.params.segment<3>(3).cwiseAbs();
  return size.minCoeff() > 0.1 * size.maxCoeff();
}

}  // namespace

namespace {

// The boundary pixels whose gradient lies within 20 degrees of the boundary's dominant
// orientation (a histogram of gradient angles modulo 180, weighted by magnitude): a pipe's
// two limbs, without the vertical edges of the blocks it rests on. Empty when under half
// the boundary or no orientation dominates.
std::vector<cv::Point> LimbPixels(const std::vector<cv::Point>& boundary,
                                  const Gradients& gradients) {
  constexpr int kBins = 36;
  std::array<double, kBins> hist{};
  std::vector<double> angle(boundary.size());
  double total = 0;
  for (size_t i = 0; i < boundary.size(); ++i) {
    const Eigen::Vector2d g = gradients.At(Eigen::Vector2d(boundary[i].x, boundary[i].y));
    double a = std::atan2(g.y(), g.x());
    if (a < 0) a += M_PI;
    if (a >= M_PI) a -= M_PI;
    angle[i] = a;
    const double m = g.norm();
    hist[static_cast<int>(a / M_PI * kBins) % kBins] += m;
    total += m;
  }
  int best = 0;
  double best_sum = -1;
  for (int b = 0; b < kBins; ++b) {
    const double sum = hist[(b + kBins - 1) % kBins] + hist[b] + hist[(b + 1) % kBins];
    if (sum > best_sum) {
      best_sum = sum;
      best = b;
    }
  }
  if (best_sum < 0.3 * total) return {};
  const double dominant = (best + 0.5) * M_PI / kBins;
  std::vector<cv::Point> out;
  for (size_t i = 0; i < boundary.size(); ++i) {
    double d = std::abs(angle[i] - dominant);
    d = std::min(d, M_PI - d);
    if (d < 20 * M_PI / 180) out.push_back(boundary[i]);
  }
  if (out.size() < boundary.size() / 2) return {};
  return out;
}

}  // namespace

std::vector<Eigen::VectorXd> CylinderStarts(const StereoPair& pair,
                                            const std::vector<cv::Point>& boundary, double depth,
                                            const DepthSearch& search, const LocateOptions& options,
                                            const Gradients* gradients) {
  const geometry::ProjectiveCamera& left_camera = *pair.left_camera;
  std::vector<Eigen::VectorXd> starts;
  auto from_points = [&](const std::vector<cv::Point>& pixels, bool tilted_too) {
    const std::vector<cv::Point2f> points(pixels.begin(), pixels.end());
    const cv::RotatedRect rr = cv::minAreaRect(points);
    cv::Point2f c[4];
    rr.points(c);
    Eigen::Vector2d e01(c[1].x - c[0].x, c[1].y - c[0].y), e12(c[2].x - c[1].x, c[2].y - c[1].y);
    if (e01.norm() < e12.norm()) std::swap(e01, e12);
    const Eigen::Vector2d along = e01.normalized(), across = e12.normalized();
    const double half_len = std::max(1.0, 0.5 * e01.norm() - 1.0);
    const double half_width = std::max(0.5, 0.5 * e12.norm() - 1.0);
    const Eigen::Vector2d mid(rr.center.x, rr.center.y);
    const double radius = 0.5 * (PointOnPixelRay(left_camera, mid + half_width * across, depth) -
                                 PointOnPixelRay(left_camera, mid - half_width * across, depth))
                                    .norm();
    const double axis_depth = depth + radius;
    Eigen::VectorXd x0(7);
    x0.segment<3>(0) =
        PointOnPixelRay(left_camera, mid - (half_len - 0.5 * half_width) * along, axis_depth);
    x0.segment<3>(3) =
        PointOnPixelRay(left_camera, mid + (half_len - 0.5 * half_width) * along, axis_depth);
    x0[6] = radius;
    starts.push_back(x0);
    if (!tilted_too) return;
    const auto tilted = TiltedCylinderStart(pair, search, x0, mid, along, half_len, half_width,
                                            depth, radius, options);
    if (tilted && std::abs(left_camera.Depth(tilted->segment<3>(0)) -
                           left_camera.Depth(tilted->segment<3>(3))) > radius)
      starts.push_back(*tilted);
  };
  from_points(boundary, true);
  // A pipe on supports: its limbs alone, when the blocks' edges widen the boundary.
  if (gradients) {
    const std::vector<cv::Point> limbs = LimbPixels(boundary, *gradients);
    auto width = [](const std::vector<cv::Point>& pixels) {
      const cv::RotatedRect r =
          cv::minAreaRect(std::vector<cv::Point2f>(pixels.begin(), pixels.end()));
      return std::min(r.size.width, r.size.height);
    };
    // Only when the blocks' edges made the boundary clearly wider than the limbs.
    if (limbs.size() >= 8 && width(limbs) < 0.8 * width(boundary) - 1) from_points(limbs, false);
  }
  return starts;
}

std::optional<Eigen::VectorXd> CylinderStretchedToMarks(const Eigen::VectorXd& start,
                                                        const MarkedRegion& marks,
                                                        const geometry::ProjectiveCamera& camera,
                                                        double margin) {
  // Where the start's axis ends lie in the left image, and the marked rectangle shrunk by the
  // margin and the radius: the axis line through the start's middle may reach its border.
  const auto a = camera.Project(start.segment<3>(0)), b = camera.Project(start.segment<3>(3));
  if (!a || !b || (*b - *a).norm() < 1e-6 || marks.hull.empty()) return std::nullopt;
  Eigen::Vector2d lo(1e18, 1e18), hi(-1e18, -1e18);
  for (const auto& p : marks.hull) {
    lo = lo.cwiseMin(Eigen::Vector2d(p.x, p.y));
    hi = hi.cwiseMax(Eigen::Vector2d(p.x, p.y));
  }
  const Eigen::Vector2d c = 0.5 * (lo + hi);
  const double depth =
      0.5 * (camera.Depth(start.segment<3>(0)) + camera.Depth(start.segment<3>(3)));
  const double unit = (PointOnPixelRay(camera, c + Eigen::Vector2d(1, 0), depth) -
                       PointOnPixelRay(camera, c, depth))
                          .norm();
  const double radius_px = std::abs(start[6]) / std::max(1e-9, unit);
  const double shrink = margin / std::max(1e-9, unit) + radius_px;
  lo += Eigen::Vector2d::Constant(shrink);
  hi -= Eigen::Vector2d::Constant(shrink);
  const Eigen::Vector2d mid = 0.5 * (*a + *b), dir = (*b - *a).normalized();
  if ((mid.array() < lo.array()).any() || (mid.array() > hi.array()).any()) return std::nullopt;
  double t_max = 1e18, t_min = -1e18;
  for (int k = 0; k < 2; ++k) {
    if (std::abs(dir[k]) < 1e-9) continue;
    const double t1 = (lo[k] - mid[k]) / dir[k], t2 = (hi[k] - mid[k]) / dir[k];
    t_max = std::min(t_max, std::max(t1, t2));
    t_min = std::max(t_min, std::min(t1, t2));
  }
  const double half = 0.5 * (*b - *a).norm();
  if (t_max - t_min < 2 * half + 3) return std::nullopt;
  Eigen::VectorXd x = start;
  x.segment<3>(0) = PointOnPixelRay(camera, mid + t_min * dir, camera.Depth(start.segment<3>(0)));
  x.segment<3>(3) = PointOnPixelRay(camera, mid + t_max * dir, camera.Depth(start.segment<3>(3)));
  return x;
}

namespace {

// The boundary's mean pixel, and the world's vertical as the left camera sees it there at
// `depth` (`up`, and `across` it). nullopt for under 8 pixels or a camera looking straight
// down.
struct UprightFrame {
  Eigen::Vector2d mean, up, across;
};
std::optional<UprightFrame> BoundaryUpright(const geometry::ProjectiveCamera& left_camera,
                                            const std::vector<cv::Point>& boundary, double depth) {
  if (boundary.size() < 8) return std::nullopt;
  UprightFrame f;
  f.mean = Eigen::Vector2d::Zero();
  for (const auto& p : boundary) f.mean += Eigen::Vector2d(p.x, p.y) / boundary.size();
  const Eigen::Vector3d X = PointOnPixelRay(left_camera, f.mean, depth);
  const auto a = left_camera.Project(X), b = left_camera.Project(X + Eigen::Vector3d::UnitZ());
  if (!a || !b || (*b - *a).norm() < 1e-9) return std::nullopt;
  f.up = (*b - *a).normalized();
  f.across = Eigen::Vector2d(-f.up.y(), f.up.x());
  return f;
}

// The boundary pixels between a block's outermost vertical edges (those whose gradient runs
// across the world's vertical as the left camera sees it, gathered by their position across
// it; an edge is a run at least half the longest): without a pipe resting on the block and
// reaching past its sides. Empty when no two such edges stand apart or they span the
// boundary anyway.
std::vector<cv::Point> BetweenVerticalEdges(const geometry::ProjectiveCamera& left_camera,
                                            const std::vector<cv::Point>& boundary, double depth,
                                            const Gradients& gradients) {
  const auto frame = BoundaryUpright(left_camera, boundary, depth);
  if (!frame) return {};
  const Eigen::Vector2d &up = frame->up, &across = frame->across;
  double lo = 1e18, hi = -1e18;
  for (const auto& p : boundary) {
    const double c = across.dot(Eigen::Vector2d(p.x, p.y));
    lo = std::min(lo, c);
    hi = std::max(hi, c);
  }
  const int bins = static_cast<int>(hi - lo) + 1;
  if (bins < 6) return {};
  std::vector<int> count(bins, 0);
  for (const auto& p : boundary) {
    const Eigen::Vector2d q(p.x, p.y);
    const Eigen::Vector2d g = gradients.At(q);
    if (std::abs(g.dot(across)) < std::cos(20 * M_PI / 180) * g.norm()) continue;
    ++count[static_cast<int>(across.dot(q) - lo)];
  }
  // Runs over 3 bins: an edge blurred over neighbouring columns.
  std::vector<int> run(bins, 0);
  for (int i = 0; i < bins; ++i)
    for (int j = std::max(0, i - 1); j <= std::min(bins - 1, i + 1); ++j) run[i] += count[j];
  const int longest = *std::max_element(run.begin(), run.end());
  if (longest < 6) return {};
  int first = -1, last = -1;
  for (int i = 0; i < bins; ++i)
    if (run[i] >= longest / 2) {
      if (first < 0) first = i;
      last = i;
    }
  if (last - first < 4 || (first <= 2 && last >= bins - 3)) return {};
  std::vector<cv::Point> out;
  for (const auto& p : boundary) {
    const double c = across.dot(Eigen::Vector2d(p.x, p.y)) - lo;
    if (c >= first - 1.5 && c <= last + 1.5) out.push_back(p);
  }
  return out;
}

// A block turned by `yaw` from its silhouette: its near bottom corner is the boundary's lowest
// pixel at `depth`; its two bottom edges recede from there along the yaw's two directions
// until they reach the boundary's sides, and its height brings the far top corner to the
// boundary's top (each a ratio of linear functions of the length, solved in closed form).
std::optional<Eigen::VectorXd> TurnedBoxStart(const geometry::ProjectiveCamera& left_camera,
                                              const std::vector<cv::Point>& boundary, double depth,
                                              double yaw) {
  const auto frame = BoundaryUpright(left_camera, boundary, depth);
  if (!frame) return std::nullopt;
  const Eigen::Vector2d &mean = frame->mean, &up = frame->up, &across = frame->across;
  Eigen::Vector2d lowest = mean;
  double left = 1e18, right = -1e18, top = -1e18;
  for (const auto& p : boundary) {
    const Eigen::Vector2d q(p.x, p.y);
    if (up.dot(q) < up.dot(lowest)) lowest = q;
    left = std::min(left, across.dot(q));
    right = std::max(right, across.dot(q));
    top = std::max(top, up.dot(q));
  }
  const Eigen::Matrix<double, 3, 4>& P = left_camera.P();
  // The length t along world direction e that brings the image coordinate along `dir` to
  // `target`: dir . (m + t n)_xy = target (m + t n)_z with n = P e.
  const auto reach = [&](const Eigen::Vector3d& from, const Eigen::Vector3d& e,
                         const Eigen::Vector2d& dir, double target) {
    const Eigen::Vector3d m0 = P.leftCols<3>() * from + P.col(3), n = P.leftCols<3>() * e;
    const double den = dir.dot(n.head<2>()) - target * n.z();
    return std::abs(den) < 1e-12 ? -1.0 : (target * m0.z() - dir.dot(m0.head<2>())) / den;
  };
  const Eigen::Vector3d view = left_camera.ViewDirection().normalized();
  Eigen::Vector3d d1(std::cos(yaw), std::sin(yaw), 0), d2(-std::sin(yaw), std::cos(yaw), 0);
  if (d1.dot(view) < 0) d1 = -d1;  // both bottom edges recede from the near corner
  if (d2.dot(view) < 0) d2 = -d2;
  const double mid_up = up.dot(mean);
  const double extent = (PointOnPixelRay(left_camera, left * across + mid_up * up, depth) -
                         PointOnPixelRay(left_camera, right * across + mid_up * up, depth))
                            .norm();
  // The match's depth is the visible faces', a quarter of their recession behind the corner:
  // the corner found at `depth`, then again that much nearer.
  Eigen::Vector3d corner;
  double s1 = 0, s2 = 0;
  for (double corner_depth = depth, pass = 0; pass < 2; ++pass) {
    corner = PointOnPixelRay(left_camera, lowest, corner_depth);
    const Eigen::Vector3d m = P.leftCols<3>() * corner + P.col(3);
    // Which edge runs to the left in the image.
    const auto moves = [&](const Eigen::Vector3d& e) {
      const Eigen::Vector3d n = P.leftCols<3>() * e;
      return across.dot(n.head<2>() * m.z() - m.head<2>() * n.z());
    };
    const bool d1_left = moves(d1) < moves(d2);
    s1 = std::clamp(reach(corner, d1, across, d1_left ? left : right), 0.05 * extent, 2.0 * extent);
    s2 = std::clamp(reach(corner, d2, across, d1_left ? right : left), 0.05 * extent, 2.0 * extent);
    corner_depth = depth - 0.25 * (s1 * d1 + s2 * d2).dot(view);
  }
  const Eigen::Vector3d far = corner + s1 * d1 + s2 * d2;
  const double h =
      std::clamp(reach(far, Eigen::Vector3d::UnitZ(), up, top), 0.05 * extent, 4.0 * extent);
  // Sizes along the box's own axes: d1 is +-x, d2 is +-y.
  Eigen::VectorXd v(7);
  v << corner + 0.5 * (s1 * d1 + s2 * d2) + 0.5 * h * Eigen::Vector3d::UnitZ(), s1, s2, h, yaw;
  return v;
}

}  // namespace

std::vector<double> HorizontalEdgeYaws(const geometry::ProjectiveCamera& left_camera,
                                       const std::vector<cv::Point>& boundary, double depth,
                                       const Gradients& gradients, int count) {
  constexpr int kBins = 45;  // 2 degrees each
  std::vector<double> hist(kBins, 0.0);
  for (const auto& p : boundary) {
    const Eigen::Vector2d q(p.x, p.y);
    const Eigen::Vector2d n = gradients.At(q);
    const double mag = n.norm();
    if (mag <= 0) continue;
    const Eigen::Matrix<double, 2, 3> J =
        geometry::ProjectionJacobian(left_camera.P(), PointOnPixelRay(left_camera, q, depth));
    if (!J.allFinite()) continue;
    const Eigen::Vector2d up = (J * Eigen::Vector3d::UnitZ()).normalized();
    const Eigen::Vector2d tangent = Eigen::Vector2d(-n.y(), n.x()) / mag;
    if (std::abs(tangent.dot(up)) > std::cos(30 * M_PI / 180)) continue;
    // The horizontal D along the edge: normal to the gradient after projection, n' J D = 0.
    const Eigen::Vector3d w = J.transpose() * n;
    const double yaw = std::atan2(-w.x(), w.y());
    double folded = std::remainder(yaw * 180 / M_PI, 90.0);  // [-45, 45]
    const int bin = std::clamp(static_cast<int>(std::floor((folded + 45.0) / 2.0)), 0, kBins - 1);
    hist[bin] += mag;
  }
  std::vector<double> smooth(kBins, 0.0);
  for (int i = 0; i < kBins; ++i)
    for (int d = -1; d <= 1; ++d) smooth[i] += (d == 0 ? 2.0 : 1.0) * hist[(i + d + kBins) % kBins];
  std::vector<double> yaws;
  std::vector<bool> taken(kBins, false);
  const double top = *std::max_element(smooth.begin(), smooth.end());
  while (static_cast<int>(yaws.size()) < count && top > 0) {
    int best = -1;
    for (int i = 0; i < kBins; ++i)
      if (!taken[i] && (best < 0 || smooth[i] > smooth[best])) best = i;
    if (best < 0 || smooth[best] < 0.75 * top) break;
    for (int d = -5; d <= 5; ++d) taken[(best + d + kBins) % kBins] = true;
    yaws.push_back((-45.0 + 2.0 * best + 1.0) * M_PI / 180);
  }
  return yaws;
}

std::vector<Eigen::VectorXd> BoxStarts(const geometry::ProjectiveCamera& left_camera,
                                       const std::vector<cv::Point>& boundary, double depth,
                                       const Gradients* gradients) {
  std::vector<Eigen::VectorXd> starts = BoxStartsFrom(left_camera, boundary, depth);
  if (gradients) {
    const std::vector<cv::Point> inner =
        BetweenVerticalEdges(left_camera, boundary, depth, *gradients);
    if (inner.size() >= 8)
      for (auto& st : BoxStartsFrom(left_camera, inner, depth)) starts.push_back(std::move(st));
    // A block turned about the vertical: one start at each yaw its horizontal edges show,
    // none when the strongest says it is not turned.
    const std::vector<double> yaws =
        HorizontalEdgeYaws(left_camera, boundary, depth, *gradients, 2);
    for (const double yaw : yaws) {
      if (std::abs(yaws[0]) < 5 * M_PI / 180) break;
      if (std::abs(yaw) < 5 * M_PI / 180) continue;
      if (auto st = TurnedBoxStart(left_camera, boundary, depth, yaw)) starts.push_back(*st);
      if (inner.size() >= 8)
        if (auto st = TurnedBoxStart(left_camera, inner, depth, yaw)) starts.push_back(*st);
    }
  }
  return starts;
}

std::vector<Eigen::VectorXd> BoxStartsFrom(const geometry::ProjectiveCamera& left_camera,
                                           const std::vector<cv::Point>& boundary, double depth) {
  const Eigen::Vector3d view_dir = left_camera.P().block<1, 3>(2, 0).transpose().normalized() *
                                   (left_camera.P().leftCols<3>().determinant() < 0 ? -1.0 : 1.0);
  int k;
  view_dir.cwiseAbs().maxCoeff(&k);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e18), hi = -lo, sum = Eigen::Vector3d::Zero();
  for (const auto& p : boundary) {
    const Eigen::Vector3d X = PointOnPixelRay(left_camera, Eigen::Vector2d(p.x, p.y), depth);
    lo = lo.cwiseMin(X);
    hi = hi.cwiseMax(X);
    sum += X;
  }
  double across_mean = 0;
  for (int i = 0; i < 3; ++i)
    if (i != k) across_mean += 0.5 * (hi[i] - lo[i]);
  const double front = sum[k] / static_cast<double>(boundary.size());
  const double back = front + (view_dir[k] > 0 ? 1 : -1) * across_mean;
  lo[k] = std::min(front, back);
  hi[k] = std::max(front, back);
  std::vector<Eigen::VectorXd> starts = {BoxParams(lo, hi, 0)};
  for (const double share : {0.4, 1.8}) {
    const double other = front + (view_dir[k] > 0 ? 1 : -1) * share * across_mean;
    Eigen::Vector3d a = lo, b = hi;
    a[k] = std::min(front, other);
    b[k] = std::max(front, other);
    starts.push_back(BoxParams(a, b, 0));
  }
  return starts;
}

FitOptions FitSettings(const LocateOptions& options, double strongest) {
  FitOptions fit;
  fit.search_px = options.search_px;
  fit.min_gradient = std::max(options.min_edge_gradient, 0.25 * strongest);
  fit.edge_blur_px = std::hypot(options.edge_sigma, options.camera_blur_px);
  fit.outer_iterations = options.outer_iterations;
  fit.inner_iterations = options.inner_iterations;
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

FitOutcome FitFromStarts(const OutlineFn& outline, const InnerEdgesFn& inner,
                         const std::vector<Eigen::VectorXd>& starts,
                         const std::array<FitView, 2>& views, const FitOptions& fit,
                         const PlausibleFn& plausible) {
  // Plausible fits first, then by score.
  const auto better = [&](const FitOutcome& a, const FitOutcome& b) {
    if (plausible && a.ok && b.ok) {
      const bool pa = plausible(a), pb = plausible(b);
      if (pa != pb) return pa;
    }
    return FitScore(a) < FitScore(b);
  };
  FitOptions first = fit;
  first.step = Eigen::VectorXd::Constant(starts[0].size(), 1e-4);
  first.outer_iterations =
      starts.size() == 1 ? fit.outer_iterations : std::min(2, fit.outer_iterations);
  FitOutcome best = FitSilhouette(outline, starts[0], views, first, inner);
  for (size_t i = 1; i < starts.size(); ++i) {
    FitOutcome g = FitSilhouette(outline, starts[i], views, first, inner);
    spdlog::debug("locate: another start: score {:.3f} against {:.3f}", FitScore(g),
                  FitScore(best));
    if (better(g, best)) best = std::move(g);
  }
  if (best.ok && first.outer_iterations < fit.outer_iterations) {
    FitOptions rest = first;
    rest.outer_iterations = fit.outer_iterations;
    rest.first_outer = first.outer_iterations;
    best = FitSilhouette(outline, best.params, views, rest, inner);
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
                                     const FitOptions& fit) {
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
