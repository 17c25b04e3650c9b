// Steps 0-3 of the locator (locate_steps.h): the images, the marks, the boundary and the
// stereo match.
#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "common/geometry/triangulation.h"
#include "object_server/locate_steps.h"
#include "object_server/solid_models.h"

namespace igms::object {
namespace {

cv::Mat Gray(const cv::Mat& img) {
  if (img.type() == CV_8UC1) return img;
  cv::Mat g;
  if (img.type() == CV_8UC3) cv::cvtColor(img, g, cv::COLOR_BGR2GRAY);
  return g;
}

// The image in ideal pixels: a camera with lens distortion is undistorted first.
cv::Mat Ideal(const cv::Mat& gray, const geometry::ProjectiveCamera& cam) {
  if (gray.empty() || !cam.has_distortion()) return gray;
  cv::Mat K, dist, out;
  cv::eigen2cv(cam.lens()->K, K);
  dist = cv::Mat(cam.lens()->dist, true);
  cv::undistort(gray, out, K, dist, K);
  return out;
}

cv::Rect ImageRect(const cv::Mat& image) { return cv::Rect(0, 0, image.cols, image.rows); }

}  // namespace

std::string FormatFixed(double v, int precision) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(precision);
  s << v;
  return s.str();
}

Eigen::Vector3d PointOnPixelRay(const geometry::ProjectiveCamera& camera, const Eigen::Vector2d& p,
                                double depth) {
  const geometry::Ray ray = camera.PixelRay(p);
  const double rate = camera.Depth(ray.origin + ray.direction);
  return ray.origin + ray.direction * (depth / rate);
}

StepResult<StereoPair> PrepareImages(const LocateInput& in) {
  StereoPair pair;
  pair.left = Ideal(Gray(in.left), in.left_camera);
  pair.right = Ideal(Gray(in.right), in.right_camera);
  pair.left_camera = &in.left_camera;
  pair.right_camera = &in.right_camera;
  const auto lsize = in.left_camera.image_size(), rsize = in.right_camera.image_size();
  if (pair.left.empty() || pair.right.empty())
    return StepFailure{Failure::kBadInput, "both images must be 8-bit grey or BGR and not empty"};
  if (pair.left.cols != lsize.width || pair.left.rows != lsize.height ||
      pair.right.cols != rsize.width || pair.right.rows != rsize.height)
    return StepFailure{Failure::kBadInput, "image sizes do not match the calibration (" +
                                               std::to_string(lsize.width) + "x" +
                                               std::to_string(lsize.height) + ")"};
  return pair;
}

StepResult<MarkedRegion> MarkRegion(const LocateInput& in) {
  for (const auto& m : in.marks)
    if (!m.allFinite()) return StepFailure{Failure::kBadInput, "a mark is not a finite point"};
  MarkedRegion region;
  double depth_sum = 0;
  std::vector<cv::Point2f> quad;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d& m = in.marks[i];
    const std::string name = "mark " + std::to_string(i + 1);
    if (in.left_camera.Depth(m) <= 1e-6 || in.right_camera.Depth(m) <= 1e-6)
      return StepFailure{Failure::kMarksBehindCamera, name + " is behind a camera"};
    // In front of the camera yet so far to the side that its image is at infinity.
    const auto p = in.left_camera.Project(m);
    if (!p)
      return StepFailure{Failure::kMarksOutsideImage,
                         name +
                             " does not project into the left image: it lies too far to the "
                             "side"};
    quad.emplace_back(static_cast<float>(p->x()), static_cast<float>(p->y()));
    depth_sum += in.left_camera.Depth(m);
  }
  region.depth = depth_sum / 4;
  cv::convexHull(quad, region.hull);
  const double area = cv::contourArea(region.hull);
  if (region.hull.size() < 3 || area < 16.0)
    return StepFailure{Failure::kMarksDegenerate, "the marks bound " + FormatFixed(area, 1) +
                                                      " square pixels in the left image; "
                                                      "place them around the object's outline"};
  const auto size = in.left_camera.image_size();
  std::vector<cv::Point2f> clipped;
  const float width = static_cast<float>(size.width), height = static_cast<float>(size.height);
  const std::vector<cv::Point2f> frame = {
      {-0.5f, -0.5f}, {width - 0.5f, -0.5f}, {width - 0.5f, height - 0.5f}, {-0.5f, height - 0.5f}};
  const double inside_area = cv::intersectConvexConvex(region.hull, frame, clipped);
  if (inside_area < 0.5 * area)
    return StepFailure{Failure::kMarksOutsideImage,
                       "most of the marked region lies outside the left image"};
  return region;
}

std::optional<LocateOptions> NoiseFloorOptions(const LocateInput& in, const StereoPair& pair,
                                               LocateOptions options) {
  if (!(options.retry_noise_gradient > 0)) return std::nullopt;
  const StepResult<MarkedRegion> marks = MarkRegion(in);
  if (!marks.ok()) return std::nullopt;
  const double noise = NoiseSigma(pair.left, cv::boundingRect(marks->hull));
  const double floor =
      std::max(options.retry_noise_gradient * noise, options.retry_min_edge_gradient);
  spdlog::debug("locate: the image's noise over the marks {:.2f}: gradient floor {:.2f}", noise,
                floor);
  if (!(floor < options.min_edge_gradient)) return std::nullopt;
  options.min_edge_gradient = floor;
  return options;
}

int RegionPad(const LocateOptions& options) {
  return static_cast<int>(std::ceil(options.search_px + options.boundary_grow_px)) + 4;
}

cv::Rect GrowRect(const cv::Rect& rect, int pad, const cv::Rect& image) {
  return cv::Rect(rect.x - pad, rect.y - pad, rect.width + 2 * pad, rect.height + 2 * pad) & image;
}

std::vector<cv::Point2f> GrowPolygon(const std::vector<cv::Point2f>& polygon, double by) {
  std::vector<cv::Point2f> grown;
  cv::Point2f centre(0, 0);
  for (const auto& p : polygon) centre += p * (1.0f / static_cast<float>(polygon.size()));
  for (const auto& p : polygon) {
    const cv::Point2f d = p - centre;
    const float len = std::sqrt(d.dot(d));
    grown.push_back(len > 0 ? p + d * (static_cast<float>(by) / len) : p);
  }
  return grown;
}

std::vector<cv::Point> LargestConnected(const std::vector<cv::Point>& pixels) {
  if (pixels.size() < 2) return pixels;
  const cv::Rect box = cv::boundingRect(pixels);
  cv::Mat mask = cv::Mat::zeros(box.height + 2, box.width + 2, CV_8U);
  for (const auto& p : pixels) mask.at<uint8_t>(p.y - box.y + 1, p.x - box.x + 1) = 255;
  cv::dilate(mask, mask, cv::Mat());
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  std::vector<int> count(n, 0);
  for (const auto& p : pixels) ++count[labels.at<int>(p.y - box.y + 1, p.x - box.x + 1)];
  const int best =
      static_cast<int>(std::max_element(count.begin() + 1, count.end()) - count.begin());
  std::vector<cv::Point> out;
  for (const auto& p : pixels)
    if (labels.at<int>(p.y - box.y + 1, p.x - box.x + 1) == best) out.push_back(p);
  return out;
}

Boundary FindBoundary(const Gradients& left_gradients, const MarkedRegion& marks,
                      const cv::Mat& edge_map, const LocateOptions& options) {
  Boundary b;
  b.region = GrowPolygon(marks.hull, options.boundary_grow_px);
  b.pixels = LargestConnected(StrongEdgePixels(left_gradients, b.region, edge_map,
                                               options.edge_fraction, options.min_edge_gradient,
                                               &b.strongest, options.edge_strength_quantile));
  return b;
}

std::vector<KnownInFront> KnownSolidsInFront(const LocateInput& in, const MarkedRegion& marks,
                                             const LocateOptions& options) {
  std::vector<KnownInFront> out;
  Eigen::Vector2d centre(0, 0);
  for (const auto& p : marks.hull) centre += Eigen::Vector2d(p.x, p.y) / marks.hull.size();
  const std::array<const geometry::ProjectiveCamera*, 2> cameras = {&in.left_camera,
                                                                    &in.right_camera};
  for (const KnownShape& k : in.known) {
    const bool cylinder = k.type == SolidType::kCylinder;
    if (k.params.size() != 7 || !k.params.allFinite()) continue;
    const std::vector<Eigen::Vector3d> points =
        cylinder ? CylinderOutline(k.params) : BoxOutline(k.params);
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& X : points) nearest = std::min(nearest, in.left_camera.Depth(X));
    if (!(nearest < marks.depth + 0.5 * options.depth_tolerance)) continue;
    KnownInFront f{k.name, {}};
    bool projects = true;
    for (int v = 0; v < 2 && projects; ++v) {
      std::vector<Eigen::Vector2d> px;
      for (const auto& X : points) {
        // Beyond 1e5 px it cannot be drawn (nor hide anything in the image).
        const auto q = cameras[v]->Project(X);
        if (!q || cameras[v]->Depth(X) <= 0 || !(q->cwiseAbs().maxCoeff() < 1e5)) {
          projects = false;
          break;
        }
        px.push_back(*q);
      }
      if (!projects) break;
      const std::vector<Eigen::Vector2d> hull = ConvexHull(px);
      if (v == 0 && hull.size() >= 3 && SignedDistance(hull, centre) < 0) projects = false;
      std::vector<cv::Point2f> corners;
      corners.reserve(hull.size());
      for (const auto& q : hull)
        corners.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()));
      for (const auto& q : GrowPolygon(corners, options.hidden_grow_px))
        f.outline[v].emplace_back(q.x, q.y);
    }
    if (projects && f.outline[0].size() >= 3 && f.outline[1].size() >= 3)
      out.push_back(std::move(f));
  }
  return out;
}

cv::Mat VisibleEdgeMask(const std::vector<KnownInFront>& in_front, const cv::Mat& edge_map,
                        cv::Size image_size) {
  if (in_front.empty()) return edge_map;
  cv::Mat mask(image_size, CV_8U, cv::Scalar(255));
  if (!edge_map.empty() && edge_map.size() == image_size) mask.setTo(0, edge_map == 0);
  for (const KnownInFront& f : in_front) {
    std::vector<cv::Point> polygon;
    constexpr int kShift = 4;
    for (const auto& q : f.outline[0])
      polygon.emplace_back(cvRound(q.x() * (1 << kShift)), cvRound(q.y() * (1 << kShift)));
    cv::fillConvexPoly(mask, polygon, cv::Scalar(0), cv::LINE_8, kShift);
  }
  return mask;
}

std::string NamesInFront(const std::vector<KnownInFront>& in_front,
                         const std::vector<cv::Point2f>& hull) {
  std::vector<Eigen::Vector2d> marked;
  marked.reserve(hull.size());
  for (const auto& p : hull) marked.emplace_back(p.x, p.y);
  std::string names;
  for (const KnownInFront& k : in_front) {
    const auto inside = [](const std::vector<Eigen::Vector2d>& polygon) {
      return [&polygon](const Eigen::Vector2d& p) { return SignedDistance(polygon, p) < 0; };
    };
    const bool overlaps = std::any_of(marked.begin(), marked.end(), inside(k.outline[0])) ||
                          std::any_of(k.outline[0].begin(), k.outline[0].end(), inside(marked));
    if (overlaps) names += (names.empty() ? "" : ", ") + k.name;
  }
  return names;
}

std::optional<StepFailure> CheckBoundary(const Boundary& boundary, const MarkedRegion& marks,
                                         const LocateOptions& options) {
  if (boundary.pixels.empty())
    return StepFailure{Failure::kNoEdgeNearMarks,
                       "no edge stronger than " + FormatFixed(options.min_edge_gradient, 1) +
                           " grey levels per pixel inside the marked region of the left image "
                           "(strongest " +
                           FormatFixed(boundary.strongest, 1) + ")"};
  const double perimeter = cv::arcLength(marks.hull, true);
  if (static_cast<double>(boundary.pixels.size()) < options.min_boundary_share * perimeter)
    return StepFailure{Failure::kEdgeCountMismatch,
                       std::to_string(boundary.pixels.size()) +
                           " boundary pixels inside marks of perimeter " +
                           FormatFixed(perimeter, 0) +
                           " px: the marked region does not hold one object's outline"};
  return std::nullopt;
}

DepthSearch ObjectDepthSearch(const std::vector<cv::Point>& boundary, double mark_depth,
                              const LocateOptions& options) {
  const cv::Rect object_rect = cv::boundingRect(boundary);
  DepthSearch s;
  s.centre = Eigen::Vector2d(object_rect.x + 0.5 * (object_rect.width - 1),
                             object_rect.y + 0.5 * (object_rect.height - 1));
  s.near = std::max(0.5 * mark_depth, mark_depth - options.depth_tolerance);
  s.far = mark_depth + options.depth_tolerance;
  s.patch =
      cv::Rect(object_rect.x - 3, object_rect.y - 3, object_rect.width + 6, object_rect.height + 6);
  if (options.match_band_px > 0) {
    s.band = cv::Mat::zeros(s.patch.size(), CV_8U);
    for (const auto& p : boundary) s.band.at<uint8_t>(p - s.patch.tl()) = 255;
    const int r = static_cast<int>(std::ceil(options.match_band_px));
    cv::dilate(s.band, s.band,
               cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)));
  }
  return s;
}

SsdMatch MatchBetweenDepths(const StereoPair& pair, const DepthSearch& search, double near,
                            double far, bool banded) {
  if (banded && search.band.empty()) return SsdMatch{};
  const auto qa =
      pair.right_camera->Project(PointOnPixelRay(*pair.left_camera, search.centre, near));
  const auto qb =
      pair.right_camera->Project(PointOnPixelRay(*pair.left_camera, search.centre, far));
  if (!qa || !qb) return SsdMatch{};
  const Eigen::Vector2d offset_a = *qa - search.centre, offset_b = *qb - search.centre;
  const cv::Rect patch = search.patch & ImageRect(pair.left);
  // The band's part over a rectangle of the patch.
  const auto band_over = [&](const cv::Rect& r) {
    return banded ? search.band(cv::Rect(r.tl() - search.patch.tl(), r.size())) : cv::Mat();
  };
  SsdMatch match =
      MatchAlongSegment(pair.left, pair.right, patch, offset_a, offset_b, band_over(patch));
  match.banded = banded;
  if (match.ok) return match;
  // No depth keeps the whole patch in the right image (an object near its edge, the patch
  // taking in what lies beside it): the part of the patch that stays in at every depth.
  cv::Rect kept = patch;
  for (const Eigen::Vector2d& o : {offset_a, offset_b}) {
    if (!(o.cwiseAbs().maxCoeff() < 1e6)) return match;  // no pixel offset (a NaN, a far point)
    const cv::Rect inside(cvCeil(1 - o.x()), cvCeil(1 - o.y()), pair.right.cols - 2,
                          pair.right.rows - 2);
    kept &= inside;
  }
  constexpr int kMinSidePx = 8;
  if (kept.width < kMinSidePx || kept.height < kMinSidePx || kept == patch) return match;
  match = MatchAlongSegment(pair.left, pair.right, kept, offset_a, offset_b, band_over(kept));
  match.banded = banded;
  return match;
}

StepResult<SsdMatch> MatchObject(const StereoPair& pair, const DepthSearch& search,
                                 const LocateOptions& options) {
  const SsdMatch match = MatchBetweenDepths(pair, search, search.near, search.far);
  if (!match.ok)
    return StepFailure{Failure::kMatchOverThreshold,
                       "the object's epipolar search region for the marks' depth +/- " +
                           FormatFixed(options.depth_tolerance, 1) + " leaves the right image"};
  if (match.zncc >= options.min_match_zncc || search.band.empty()) return match;
  const SsdMatch banded = MatchBetweenDepths(pair, search, search.near, search.far, true);
  return banded.ok && banded.zncc >= options.min_match_zncc ? banded : match;
}

SsdMatch NarrowByRange(const LocateInput& in, const StereoPair& pair, const DepthSearch& search,
                       const Boundary& boundary, double mark_depth, const SsdMatch& match,
                       const LocateOptions& options, RangeCheck* check) {
  if (!in.range) return match;
  check->used = true;
  check->measured = *in.range;
  // The beam's axis point at the range is the object's front depth when it falls inside the
  // marked region and agrees with the marks; off the axis the nearest surface may lie deeper
  // by up to range * (1 - cos(half angle)).
  const Eigen::Vector3d q = in.ranger_origin + *in.range * in.ranger_axis.normalized();
  const auto qp = in.left_camera.Project(q);
  const double qd = in.left_camera.Depth(q);
  const double beam = options.ranger_accuracy +
                      *in.range * (1 - std::cos(options.ranger_half_angle_deg * M_PI / 180));
  if (qp && qd > 0 &&
      cv::pointPolygonTest(boundary.region,
                           cv::Point2f(static_cast<float>(qp->x()), static_cast<float>(qp->y())),
                           false) >= 0 &&
      std::abs(qd - mark_depth) <= options.depth_tolerance) {
    SsdMatch ranged =
        MatchBetweenDepths(pair, search, std::max(0.5 * qd, qd - beam), qd + beam, match.banded);
    if (ranged.ok && ranged.rms <= 1.25 * match.rms + 1.0) {
      check->constrained = true;
      return ranged;
    }
  }
  return match;
}

std::optional<StepFailure> CheckMatch(const SsdMatch& match, const LocateOptions& options) {
  if (match.zncc < options.min_match_zncc)
    return StepFailure{Failure::kMatchOverThreshold,
                       "best right-image match within the marks' depth +/- " +
                           FormatFixed(options.depth_tolerance, 1) + " correlates " +
                           FormatFixed(match.zncc, 2) + " (at least " +
                           FormatFixed(options.min_match_zncc, 2) + " needed; it differs by " +
                           FormatFixed(match.rms, 1) + " grey levels RMS): check the marks' depth"};
  return std::nullopt;
}

std::optional<Eigen::Vector3d> TriangulateMidpoint(const geometry::ProjectiveCamera& left_camera,
                                                   const Eigen::Vector2d& left_pixel,
                                                   const geometry::ProjectiveCamera& right_camera,
                                                   const Eigen::Vector2d& right_pixel) {
  geometry::TriangulationOptions options;
  options.pixel_sigma = 0;
  const auto t = geometry::Triangulate(left_camera.P(), right_camera.P(), left_pixel, right_pixel,
                                       geometry::TriangulationMethod::kMidpoint, options);
  if (!t.ok()) return std::nullopt;
  return t->point;
}

std::optional<Eigen::Vector3d> TriangulateMatch(const StereoPair& pair, const DepthSearch& search,
                                                const SsdMatch& match) {
  return TriangulateMidpoint(*pair.left_camera, search.centre, *pair.right_camera,
                             search.centre + match.offset);
}

cv::Rect RightRegion(const DepthSearch& search, const SsdMatch& match, int pad,
                     const cv::Rect& image) {
  const cv::Point shift(static_cast<int>(std::round(match.offset.x())),
                        static_cast<int>(std::round(match.offset.y())));
  return GrowRect(search.patch + shift, pad, image);
}

std::array<std::vector<Eigen::Vector2d>, 2> OutlineRegions(const MarkedRegion& marks,
                                                           const StereoPair& pair, double near,
                                                           double far,
                                                           const LocateOptions& options) {
  std::array<std::vector<Eigen::Vector2d>, 2> regions;
  std::vector<Eigen::Vector2d> left, right;
  for (const auto& q : GrowPolygon(marks.hull, options.boundary_grow_px)) {
    const Eigen::Vector2d p(q.x, q.y);
    left.push_back(p);
    for (const double d : {near, far}) {
      const auto r = pair.right_camera->Project(PointOnPixelRay(*pair.left_camera, p, d));
      if (!r) return regions;  // no right region: both searched unbounded
      right.push_back(*r);
    }
  }
  regions[0] = ConvexHull(left);
  regions[1] = ConvexHull(right);
  return regions;
}

cv::Mat LeftTexture(const LocateInput& in, const cv::Rect& rect) {
  return Ideal(in.left, in.left_camera)(rect).clone();
}

}  // namespace igms::object
