// Step 4 of the locator (locate_steps.h): the starting models of a cylinder (3.8.1) and a
// block (3.8.2) from the left boundary at the matched depth, before the fit.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "common/geometry/triangulation.h"
#include "object_server/locate_steps.h"
#include "object_server/solid_models.h"

namespace igms::object {
namespace {

// The shares of the boundary's rows, from its top, that a raised pipe's upper-part starts
// take: a pipe lying on a block fills the upper half to two thirds of the marked outline.
constexpr double kRaisedPipeShares[] = {0.5, 0.65};
// The yaws, degrees, a block's region between its vertical edges is also started at when the
// world-aligned fit is poor (BoxStarts, FitBox).
constexpr double kInnerTurnsDeg[] = {-36, -18, 18, 36};

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

}  // namespace

namespace {

// The pixels' offsets along `across`, in 1 px bins from the lowest: `smooth[b]` counts the
// pixels of bins b - 1 to b + 1, where a pixel's bin is Bin(i) (padded by one either side).
struct OffsetBins {
  std::vector<double> offset, smooth;
  double lo = 0;
  int Bin(size_t i) const { return static_cast<int>(offset[i] - lo) + 1; }
  // The first of the tallest bins, at least `apart` from `other` (any, for -1); -1 for none.
  int Tallest(int other = -1, int apart = 0) const {
    int best = -1;
    for (int b = 1; b + 1 < static_cast<int>(smooth.size()); ++b)
      if ((other < 0 || std::abs(b - other) >= apart) && (best < 0 || smooth[b] > smooth[best]))
        best = b;
    return best;
  }
};

OffsetBins BinOffsets(const std::vector<cv::Point>& pixels, const Eigen::Vector2d& across) {
  OffsetBins o;
  o.offset.resize(pixels.size());
  double hi = -1e18;
  o.lo = 1e18;
  for (size_t i = 0; i < pixels.size(); ++i) {
    o.offset[i] = across.dot(Eigen::Vector2d(pixels[i].x, pixels[i].y));
    o.lo = std::min(o.lo, o.offset[i]);
    hi = std::max(hi, o.offset[i]);
  }
  if (pixels.empty()) return o;
  const int bins = static_cast<int>(hi - o.lo) + 3;
  std::vector<double> hist(bins, 0.0);
  o.smooth.assign(bins, 0.0);
  for (size_t i = 0; i < pixels.size(); ++i) hist[o.Bin(i)] += 1;
  for (int b = 1; b + 1 < bins; ++b) o.smooth[b] = hist[b - 1] + hist[b] + hist[b + 1];
  return o;
}

// Of the pixels, those along the two lines across `normal` that hold the most (two peaks of
// their offsets along it, at least 3 px apart, the lower a quarter of the taller: a block in
// front may hide much of one): a leaning pipe's limbs, without its ends or the blocks'
// corners. Empty when no second line shows.
std::vector<cv::Point> AlongTwoLines(const std::vector<cv::Point>& pixels,
                                     const Eigen::Vector2d& normal) {
  const OffsetBins o = BinOffsets(pixels, normal);
  const int p1 = o.Tallest(), p2 = o.Tallest(p1, 3);
  if (p2 < 0 || 4 * o.smooth[p2] < o.smooth[p1]) return {};
  std::vector<cv::Point> out;
  for (size_t i = 0; i < pixels.size(); ++i)
    if (std::abs(o.Bin(i) - p1) <= 1 || std::abs(o.Bin(i) - p2) <= 1) out.push_back(pixels[i]);
  return out;
}

// The boundary pixels' gradient orientations (modulo 180 degrees) and their histogram,
// weighted by magnitude; a peak's weight is its bin's and its two neighbours'.
struct Orientations {
  static constexpr int kBins = 36;
  std::array<double, kBins> hist{};
  std::vector<double> angle;
  double total = 0;
  double Peak(int b) const {
    return hist[(b + kBins - 1) % kBins] + hist[b] + hist[(b + 1) % kBins];
  }
  // The strongest peak at least `apart` bins from `other` (any, for -1).
  int Strongest(int other = -1, int apart = 0) const {
    int best = -1;
    for (int b = 0; b < kBins; ++b) {
      const int d = other < 0 ? kBins : std::abs(b - other);
      if (std::min(d, kBins - d) < apart) continue;
      if (best < 0 || Peak(b) > Peak(best)) best = b;
    }
    return best;
  }
  // The pixels within 20 degrees of bin b's centre.
  std::vector<cv::Point> Near(const std::vector<cv::Point>& boundary, int b) const {
    const double at = (b + 0.5) * M_PI / kBins;
    std::vector<cv::Point> out;
    for (size_t i = 0; i < boundary.size(); ++i) {
      double d = std::abs(angle[i] - at);
      d = std::min(d, M_PI - d);
      if (d < 20 * M_PI / 180) out.push_back(boundary[i]);
    }
    return out;
  }
};

Orientations OrientationsOf(const std::vector<cv::Point>& boundary, const Gradients& gradients) {
  Orientations o;
  o.angle.resize(boundary.size());
  for (size_t i = 0; i < boundary.size(); ++i) {
    const Eigen::Vector2d g = gradients.At(Eigen::Vector2d(boundary[i].x, boundary[i].y));
    double a = std::atan2(g.y(), g.x());
    if (a < 0) a += M_PI;
    if (a >= M_PI) a -= M_PI;
    o.angle[i] = a;
    const double m = g.norm();
    o.hist[static_cast<int>(a / M_PI * Orientations::kBins) % Orientations::kBins] += m;
    o.total += m;
  }
  return o;
}

// The boundary pixels whose gradient lies within 20 degrees of the boundary's dominant
// orientation: a pipe's two limbs, without the vertical edges of the blocks it rests on,
// however many of those there are. Empty when no orientation dominates.
std::vector<cv::Point> LimbPixels(const std::vector<cv::Point>& boundary,
                                  const Gradients& gradients) {
  const Orientations o = OrientationsOf(boundary, gradients);
  const int best = o.Strongest();
  if (o.Peak(best) < 0.3 * o.total) return {};
  return o.Near(boundary, best);
}

// A pipe leaning across the block it rests on, whichever of the two dominates the boundary:
// at each of the boundary's two strongest orientations (at least 30 degrees apart, each
// holding a sixth of its gradient), the pixels along two lines (AlongTwoLines), where they
// run at least three times as long as they lie apart.
std::vector<std::vector<cv::Point>> LeaningLimbs(const std::vector<cv::Point>& boundary,
                                                 const Gradients& gradients) {
  const Orientations o = OrientationsOf(boundary, gradients);
  const int first = o.Strongest();
  const int second = o.Strongest(first, Orientations::kBins / 6);
  std::vector<std::vector<cv::Point>> out;
  for (const int b : {first, second}) {
    if (b < 0 || 6 * o.Peak(b) < o.total) continue;
    const double at = (b + 0.5) * M_PI / Orientations::kBins;
    std::vector<cv::Point> limbs =
        AlongTwoLines(o.Near(boundary, b), Eigen::Vector2d(std::cos(at), std::sin(at)));
    if (limbs.size() < 8) continue;
    const cv::RotatedRect r = cv::minAreaRect(std::vector<cv::Point2f>(limbs.begin(), limbs.end()));
    if (std::max(r.size.width, r.size.height) >= 3 * std::min(r.size.width, r.size.height))
      out.push_back(std::move(limbs));
  }
  return out;
}

// Of the limb pixels, those of the line nearest the image's top (a histogram of each pixel's
// offset across the limbs' common direction, 1 px bins; its first peak of at least a fifth of
// the tallest, and the pixels within 2 px of it): a raised pipe's upper limb, above its lower
// limb and the supports' feet. Empty unless the limbs lie within 45 degrees of the rows, where
// "up" is the image's. `lower`, when given, gets the lower limb: the pixels of the tallest
// peak below that line and clear of it (none when no such peak).
std::vector<cv::Point> TopLimbLine(const std::vector<cv::Point>& limbs, const Gradients& gradients,
                                   std::vector<cv::Point>* lower = nullptr) {
  if (limbs.size() < 16) return {};
  // The gradients' mean orientation, modulo 180 degrees (their doubled angles averaged).
  Eigen::Vector2d doubled = Eigen::Vector2d::Zero();
  for (const auto& p : limbs) {
    const Eigen::Vector2d g = gradients.At(Eigen::Vector2d(p.x, p.y));
    doubled +=
        Eigen::Vector2d(g.x() * g.x() - g.y() * g.y(), 2 * g.x() * g.y()) / (g.norm() + 1e-9);
  }
  if (doubled.norm() < 1e-9) return {};
  const double angle = 0.5 * std::atan2(doubled.y(), doubled.x());
  const Eigen::Vector2d across(std::cos(angle), std::sin(angle));
  if (std::abs(across.y()) < std::sqrt(0.5)) return {};
  const OffsetBins o = BinOffsets(limbs, across);
  const std::vector<double>& offset = o.offset;
  const std::vector<double>& smooth = o.smooth;
  const double lo = o.lo;
  const int bins = static_cast<int>(smooth.size());
  const double tallest = *std::max_element(smooth.begin(), smooth.end());
  int peak = -1;
  for (int b = 1; b + 1 < bins && peak < 0; ++b)
    if (smooth[b] >= std::max(6.0, 0.2 * tallest) && smooth[b] >= smooth[b - 1] &&
        smooth[b] >= smooth[b + 1])
      peak = b;
  // The limb pixels within 2 px of a peak's bin.
  const auto at_peak = [&](int bin, std::vector<cv::Point>* out) {
    for (size_t i = 0; i < limbs.size(); ++i)
      if (bin >= 0 && std::abs(offset[i] - lo + 1 - bin) <= 2.0) out->push_back(limbs[i]);
  };
  std::vector<cv::Point> line;
  at_peak(peak, &line);
  // The lower limb: the tallest peak below the top line, clear of it.
  if (lower && peak >= 0) {
    int second = -1;
    for (int b = peak + 4; b + 1 < bins; ++b)
      if (smooth[b] >= std::max(6.0, 0.2 * tallest) && smooth[b] >= smooth[b - 1] &&
          smooth[b] >= smooth[b + 1] && (second < 0 || smooth[b] > smooth[second]))
        second = b;
    at_peak(second, lower);
  }
  return line;
}

}  // namespace

std::vector<Eigen::VectorXd> CylinderStarts(const StereoPair& pair,
                                            const std::vector<cv::Point>& boundary, double depth,
                                            const DepthSearch& search, const LocateOptions& options,
                                            const Gradients* gradients, RaisedPipeStarts* raised) {
  const geometry::ProjectiveCamera& left_camera = *pair.left_camera;
  std::vector<Eigen::VectorXd> starts;
  // A start from the pixels' smallest rotated rectangle, into `out`.
  auto from_points = [&](const std::vector<cv::Point>& pixels, bool tilted_too,
                         std::vector<Eigen::VectorXd>* out) {
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
    out->push_back(x0);
    if (!tilted_too) return;
    const auto tilted = TiltedCylinderStart(pair, search, x0, mid, along, half_len, half_width,
                                            depth, radius, options);
    if (tilted && std::abs(left_camera.Depth(tilted->segment<3>(0)) -
                           left_camera.Depth(tilted->segment<3>(3))) > radius)
      out->push_back(*tilted);
  };
  from_points(boundary, true, &starts);
  // A pipe on supports: its limbs alone, when the blocks' edges widen the boundary.
  if (gradients) {
    const std::vector<cv::Point> limbs = LimbPixels(boundary, *gradients);
    auto width = [](const std::vector<cv::Point>& pixels) {
      const cv::RotatedRect r =
          cv::minAreaRect(std::vector<cv::Point2f>(pixels.begin(), pixels.end()));
      return std::min(r.size.width, r.size.height);
    };
    // Only when the blocks' edges made the boundary clearly wider than the limbs.
    if (limbs.size() >= 8 && width(limbs) < 0.8 * width(boundary) - 1)
      from_points(limbs, false, &starts);
    // Or the limb line nearest the top alone, as a pipe's upper limb whose lower one the
    // blocks under it hide or the background swallows: its copy a fraction of the way down to
    // the boundary's lowest pixel stands for the lower limb. Only for a line at least that
    // long (a pipe's side, not an upright's end).
    std::vector<cv::Point> lower;
    const std::vector<cv::Point> top =
        raised ? TopLimbLine(limbs, *gradients, &lower) : std::vector<cv::Point>{};
    // The two limb lines alone, where both show: the supports' edges between them left out.
    if (!top.empty() && !lower.empty()) {
      std::vector<cv::Point> both = top;
      both.insert(both.end(), lower.begin(), lower.end());
      from_points(both, false, &raised->upper_limb);
    }
    if (!top.empty()) {
      double lowest = -1e18, mean_v = 0;
      for (const auto& q : boundary) lowest = std::max(lowest, double(q.y));
      for (const auto& q : top) mean_v += q.y;
      const double below = lowest - mean_v / double(top.size());
      const cv::RotatedRect r = cv::minAreaRect(std::vector<cv::Point2f>(top.begin(), top.end()));
      if (std::max(r.size.width, r.size.height) >= below)
        for (const double f : {0.3, 0.45, 0.6}) {
          std::vector<cv::Point> pixels = top;
          for (const auto& q : top)
            pixels.emplace_back(q.x, q.y + static_cast<int>(std::lround(f * below)));
          from_points(pixels, false, &raised->upper_limb);
        }
    }
  }
  if (gradients && raised)
    for (const auto& limbs : LeaningLimbs(boundary, *gradients))
      from_points(limbs, true, &raised->crossing);
  if (raised && raised->with_upper_part) {
    double top = 1e18, bottom = -1e18;
    for (const auto& q : boundary) {
      top = std::min(top, double(q.y));
      bottom = std::max(bottom, double(q.y));
    }
    for (const double share : kRaisedPipeShares) {
      std::vector<cv::Point> upper;
      for (const auto& q : boundary)
        if (q.y <= top + share * (bottom - top)) upper.push_back(q);
      if (upper.size() >= 8) from_points(upper, true, &raised->upper_part);
    }
  }
  return starts;
}

std::vector<Eigen::VectorXd> PipesBesideLimb(const Eigen::VectorXd& collapsed,
                                             const std::array<Eigen::Vector3d, 4>& marks,
                                             const geometry::ProjectiveCamera& camera) {
  const Eigen::Vector3d p0 = collapsed.segment<3>(0), p1 = collapsed.segment<3>(3);
  const Eigen::Vector3d across = (p1 - p0).cross(0.5 * (p0 + p1) - camera.Center());
  if (!(across.norm() > 1e-9)) return {};
  const Eigen::Vector3d d = across.normalized();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& m : marks) {
    lo = std::min(lo, m.dot(d));
    hi = std::max(hi, m.dot(d));
  }
  std::vector<Eigen::VectorXd> starts;
  for (const double share : kLimbRadiusShares)
    for (const double side : {-1.0, 1.0}) {
      const double r = share * (hi - lo);
      Eigen::VectorXd s(7);
      s << p0 + side * r * d, p1 + side * r * d, r;
      starts.push_back(s);
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
// it; an edge is a run at least a third as long as the longest): without a pipe resting on
// the block and reaching past its sides. An edge's length is the rows along the vertical its
// pixels cover, however wide the blur spreads it, so a block's side against the table counts
// as much as one where a pipe's limb runs on up from it. Empty when no two such edges stand
// apart or they span the boundary anyway. `under_tops`, when given, gets those pixels no
// higher than the lower of the two edges' tops, when that cuts 3 rows or more off: the block
// without the pipe resting on it, whose end or limb carries the other edge on up.
std::vector<cv::Point> BetweenVerticalEdges(const geometry::ProjectiveCamera& left_camera,
                                            const std::vector<cv::Point>& boundary, double depth,
                                            const Gradients& gradients,
                                            std::vector<cv::Point>* under_tops = nullptr) {
  const auto frame = BoundaryUpright(left_camera, boundary, depth);
  if (!frame) return {};
  const Eigen::Vector2d &across = frame->across, &up = frame->up;
  double lo = 1e18, hi = -1e18, up_lo = 1e18, up_hi = -1e18;
  for (const auto& p : boundary) {
    const Eigen::Vector2d q(p.x, p.y);
    lo = std::min(lo, across.dot(q));
    hi = std::max(hi, across.dot(q));
    up_lo = std::min(up_lo, up.dot(q));
    up_hi = std::max(up_hi, up.dot(q));
  }
  const int bins = static_cast<int>(hi - lo) + 1, rows = static_cast<int>(up_hi - up_lo) + 1;
  if (bins < 6) return {};
  // The rows each column's vertical-edge pixels cover.
  std::vector<std::vector<char>> covers(bins, std::vector<char>(rows, 0));
  for (const auto& p : boundary) {
    const Eigen::Vector2d q(p.x, p.y);
    const Eigen::Vector2d g = gradients.At(q);
    if (std::abs(g.dot(across)) < std::cos(20 * M_PI / 180) * g.norm()) continue;
    covers[static_cast<int>(across.dot(q) - lo)][static_cast<int>(up.dot(q) - up_lo)] = 1;
  }
  // Runs over 3 columns: an edge blurred over neighbouring columns.
  std::vector<int> run(bins, 0);
  for (int i = 0; i < bins; ++i)
    for (int r = 0; r < rows; ++r)
      for (int j = std::max(0, i - 1); j <= std::min(bins - 1, i + 1); ++j)
        if (covers[j][r]) {
          ++run[i];
          break;
        }
  const int longest = *std::max_element(run.begin(), run.end());
  if (longest < 6) return {};
  int first = -1, last = -1;
  for (int i = 0; i < bins; ++i)
    if (run[i] >= longest / 3) {
      if (first < 0) first = i;
      last = i;
    }
  if (last - first < 4 || (first <= 2 && last >= bins - 3)) return {};
  std::vector<cv::Point> out;
  for (const auto& p : boundary) {
    const double c = across.dot(Eigen::Vector2d(p.x, p.y)) - lo;
    if (c >= first - 1.5 && c <= last + 1.5) out.push_back(p);
  }
  if (under_tops) {
    // Each outer edge's top: the highest row its columns cover. The lower of the two is the
    // block's top when a pipe resting on it carries the other on up.
    const auto edge_top = [&](int column) {
      int top = -1;
      for (int j = std::max(0, column - 1); j <= std::min(bins - 1, column + 1); ++j)
        for (int r = 0; r < rows; ++r)
          if (covers[j][r]) top = std::max(top, r);
      return top;
    };
    const int top = std::min(edge_top(first), edge_top(last));
    if (top >= 0 && top + 3 < rows - 1)
      for (const auto& p : out)
        if (up.dot(Eigen::Vector2d(p.x, p.y)) - up_lo <= top + 1.5) under_tops->push_back(p);
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
                                       const Gradients* gradients,
                                       std::vector<Eigen::VectorXd>* if_poor) {
  std::vector<Eigen::VectorXd> starts = BoxStartsFrom(left_camera, boundary, depth);
  if (gradients) {
    std::vector<cv::Point> under_tops;
    const std::vector<cv::Point> inner =
        BetweenVerticalEdges(left_camera, boundary, depth, *gradients, &under_tops);
    if (inner.size() >= 8)
      for (auto& st : BoxStartsFrom(left_camera, inner, depth)) starts.push_back(std::move(st));
    if (under_tops.size() >= 8)  // and under the lower of their tops
      for (auto& st : BoxStartsFrom(left_camera, under_tops, depth))
        starts.push_back(std::move(st));
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
    if (if_poor && inner.size() >= 8)
      for (const double turn_deg : kInnerTurnsDeg)
        if (auto st = TurnedBoxStart(left_camera, inner, depth, turn_deg * M_PI / 180))
          if_poor->push_back(*st);
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

}  // namespace igms::object
