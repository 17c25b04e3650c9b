#include "object_server/locate.h"

#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "common/geometry/triangulation.h"
#include "object_server/image_ops.h"
#include "object_server/ranger.h"
#include "object_server/silhouette_fit.h"
#include "object_server/solid_models.h"

namespace igms::object {
namespace {

using Clock = std::chrono::steady_clock;

LocateResult Fail(LocateResult r, Failure reason, std::string detail) {
  r.found = false;
  r.reason = reason;
  r.detail = std::move(detail);
  return r;
}

std::string Fmt(double v, int precision = 2) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(precision);
  s << v;
  return s.str();
}

// The point on pixel p's ray at left-camera depth d.
Eigen::Vector3d AtDepth(const geometry::ProjectiveCamera& cam, const Eigen::Vector2d& p, double d) {
  const geometry::Ray ray = cam.PixelRay(p);
  const double rate = cam.Depth(ray.origin + ray.direction);
  return ray.origin + ray.direction * (d / rate);
}

// Midpoint triangulation of the match (Cooke, 3.7); only a starting depth, so the simplest.
std::optional<Eigen::Vector3d> Triangulate(const geometry::ProjectiveCamera& l,
                                           const Eigen::Vector2d& pl,
                                           const geometry::ProjectiveCamera& r,
                                           const Eigen::Vector2d& pr) {
  geometry::TriangulationOptions options;
  options.pixel_sigma = 0;
  const auto t = geometry::Triangulate(l.P(), r.P(), pl, pr,
                                       geometry::TriangulationMethod::kMidpoint, options);
  if (!t) return std::nullopt;
  return t->point;
}

// The image in ideal pixels: a camera with lens distortion is undistorted first (P maps to
// ideal pixels; the lens acts after it, as in OpenCV's model).
cv::Mat Ideal(const cv::Mat& gray, const geometry::ProjectiveCamera& cam) {
  if (gray.empty() || !cam.has_distortion()) return gray;
  cv::Mat K, dist, out;
  cv::eigen2cv(cam.lens()->K, K);
  dist = cv::Mat(cam.lens()->dist, true);
  cv::undistort(gray, out, K, dist, K);
  return out;
}

cv::Mat Gray(const cv::Mat& img) {
  if (img.type() == CV_8UC1) return img;
  cv::Mat g;
  if (img.type() == CV_8UC3) cv::cvtColor(img, g, cv::COLOR_BGR2GRAY);
  return g;
}

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

// The pixels of the largest 8-connected set among `pixels`, gaps of one pixel bridged.
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

// The range against the located solid (RangeCheck in locate.h).
void CheckRange(const LocateInput& in, const LocateOptions& opt, const Eigen::VectorXd& x,
                RangeCheck* check) {
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
  const auto beam = RangesInBeam(surface, ranger, opt.ranger_half_angle_deg * M_PI / 180, spacing);
  if (!beam) {
    check->agrees = false;
    check->detail = "the ranger's " + Fmt(2 * opt.ranger_half_angle_deg, 0) +
                    "-degree beam does not reach the located object: the range " +
                    Fmt(check->measured) + " measured something else";
    return;
  }
  check->expected_min = beam->nearest;
  check->expected_max = beam->on_axis;
  const double acc = opt.ranger_accuracy;
  if (check->measured < beam->nearest - acc) {
    check->agrees = false;
    check->detail =
        "the range " + Fmt(check->measured) + " is " + Fmt(beam->nearest - check->measured) +
        " shorter than the located object's nearest point in the beam (" + Fmt(beam->nearest) +
        "): something nearer is in the beam, or the model is wrong";
  } else if (check->measured > beam->on_axis + acc) {
    check->agrees = false;
    check->detail = "the range " + Fmt(check->measured) + " is " +
                    Fmt(check->measured - beam->on_axis) +
                    " beyond where the beam meets the located object (" + Fmt(beam->on_axis) +
                    "): the model is nearer than the ranger says";
  }
}

}  // namespace

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
  }
  return "unknown";
}

bool LocateOptions::Check(std::string* error) const {
  if (!(depth_tolerance > 0)) {
    *error = "depth_tolerance must be positive";
    return false;
  }
  if (!(edge_sigma >= 0 && edge_sigma <= 10)) {
    *error = "edge_sigma must be in 0..10";
    return false;
  }
  if (!(camera_blur_px >= 0 && camera_blur_px <= 10)) {
    *error = "camera_blur_px must be in 0..10";
    return false;
  }
  if (!(edge_fraction > 0 && edge_fraction < 1)) {
    *error = "edge_fraction must be in (0, 1)";
    return false;
  }
  if (!(search_px >= 1 && search_px <= 20)) {
    *error = "search_px must be in 1..20";
    return false;
  }
  if (outer_iterations < 1 || inner_iterations < 1) {
    *error = "iterations must be at least 1";
    return false;
  }
  if (!(max_rms_px > 0) || !(max_ssd_rms > 0)) {
    *error = "thresholds must be positive";
    return false;
  }
  return true;
}

LocateResult Locate(const LocateInput& in, const LocateOptions& opt) {
  const auto start = Clock::now();
  LocateResult res;
  res.type = in.type;
  auto finish = [&](LocateResult r) {
    r.elapsed_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return r;
  };
  if (std::string e; !opt.Check(&e))
    return finish(Fail(res, Failure::kBadInput, "options: " + e));
  const cv::Mat left = Ideal(Gray(in.left), in.left_camera),
                right = Ideal(Gray(in.right), in.right_camera);
  const auto lsize = in.left_camera.image_size(), rsize = in.right_camera.image_size();
  if (left.empty() || right.empty())
    return finish(
        Fail(res, Failure::kBadInput, "both images must be 8-bit grey or BGR and not empty"));
  if (left.cols != lsize.width || left.rows != lsize.height || right.cols != rsize.width ||
      right.rows != rsize.height)
    return finish(Fail(res, Failure::kBadInput,
                       "image sizes do not match the calibration (" + std::to_string(lsize.width) +
                           "x" + std::to_string(lsize.height) + ")"));
  for (const auto& m : in.marks)
    if (!m.allFinite())
      return finish(Fail(res, Failure::kBadInput, "a mark is not a finite point"));

  // 1. Marks.
  double depth_sum = 0;
  std::vector<cv::Point2f> quad;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d& m = in.marks[i];
    if (in.left_camera.Depth(m) <= 1e-6 || in.right_camera.Depth(m) <= 1e-6)
      return finish(Fail(res, Failure::kMarksBehindCamera,
                         "mark " + std::to_string(i + 1) + " is behind a camera"));
    const Eigen::Vector2d p = *in.left_camera.Project(m);
    quad.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
    depth_sum += in.left_camera.Depth(m);
  }
  const double mark_depth = depth_sum / 4;
  std::vector<cv::Point2f> hull4;
  cv::convexHull(quad, hull4);
  const double area = cv::contourArea(hull4);
  if (hull4.size() < 3 || area < 16.0)
    return finish(Fail(res, Failure::kMarksDegenerate,
                       "the marks bound " + Fmt(area, 1) +
                           " square pixels in the left image; "
                           "place them around the object's outline"));
  const cv::Rect image_rect(0, 0, left.cols, left.rows);
  const cv::Rect quad_rect = cv::boundingRect(hull4);
  std::vector<cv::Point2f> clipped;
  const std::vector<cv::Point2f> frame = {{-0.5f, -0.5f},
                                          {left.cols - 0.5f, -0.5f},
                                          {left.cols - 0.5f, left.rows - 0.5f},
                                          {-0.5f, left.rows - 0.5f}};
  const double inside_area = cv::intersectConvexConvex(hull4, frame, clipped);
  if (inside_area < 0.5 * area)
    return finish(Fail(res, Failure::kMarksOutsideImage,
                       "most of the marked region lies outside the left image"));

  // 2. Boundary in the left image.
  const int pad = static_cast<int>(std::ceil(opt.search_px + opt.boundary_grow_px)) + 4;
  const cv::Rect left_region = cv::Rect(quad_rect.x - pad, quad_rect.y - pad,
                                        quad_rect.width + 2 * pad, quad_rect.height + 2 * pad) &
                               image_rect;
  const Gradients grad_left(left, left_region, opt.edge_sigma);
  double strongest = 0;
  // The thesis searches up to 15 px outward from the marks (3.8.1): the region is grown by
  // boundary_grow_px so an outline the marks graze is still whole.
  std::vector<cv::Point2f> grown;
  {
    cv::Point2f centre(0, 0);
    for (const auto& p : hull4) centre += p * (1.0f / hull4.size());
    for (const auto& p : hull4) {
      const cv::Point2f d = p - centre;
      const float len = std::sqrt(d.dot(d));
      grown.push_back(len > 0 ? p + d * (static_cast<float>(opt.boundary_grow_px) / len) : p);
    }
  }
  std::vector<cv::Point> boundary = StrongEdgePixels(
      grad_left, grown, in.left_edges, opt.edge_fraction, opt.min_edge_gradient, &strongest);
  // The object is the largest connected edge (the thesis follows the boundary from the marks,
  // 3.8.1): a neighbour's edge grazed by the marks' margin must not widen its outline.
  boundary = LargestConnected(boundary);
  res.boundary_pixels = static_cast<int>(boundary.size());
  if (boundary.empty())
    return finish(Fail(res, Failure::kNoEdgeNearMarks,
                       "no edge stronger than " + Fmt(opt.min_edge_gradient, 1) +
                           " grey levels per pixel inside the marked region of the left image "
                           "(strongest " +
                           Fmt(strongest, 1) + ")"));
  const double perimeter = cv::arcLength(hull4, true);
  if (boundary.size() < opt.min_boundary_share * perimeter)
    return finish(Fail(res, Failure::kEdgeCountMismatch,
                       std::to_string(boundary.size()) +
                           " boundary pixels inside marks of perimeter " + Fmt(perimeter, 0) +
                           " px: the marked region does not hold one object's outline"));
  const cv::Rect object_rect = cv::boundingRect(boundary);

  // 3. Depth by SSD along the epipolar segment of the marks' depth range.
  const Eigen::Vector2d q_left(object_rect.x + 0.5 * (object_rect.width - 1),
                               object_rect.y + 0.5 * (object_rect.height - 1));
  const double d_near = std::max(0.5 * mark_depth, mark_depth - opt.depth_tolerance);
  const double d_far = mark_depth + opt.depth_tolerance;
  const cv::Rect patch(object_rect.x - 3, object_rect.y - 3, object_rect.width + 6,
                       object_rect.height + 6);
  auto match_between = [&](double near, double far) {
    const auto qa = in.right_camera.Project(AtDepth(in.left_camera, q_left, near));
    const auto qb = in.right_camera.Project(AtDepth(in.left_camera, q_left, far));
    if (!qa || !qb) return SsdMatch{};
    return MatchAlongSegment(left, right, patch & image_rect, *qa - q_left, *qb - q_left);
  };
  SsdMatch match = match_between(d_near, d_far);
  if (!match.ok)
    return finish(Fail(res, Failure::kMatchOverThreshold,
                       "the object's epipolar search region for the marks' depth +/- " +
                           Fmt(opt.depth_tolerance, 1) + " leaves the right image"));
  if (in.range) {
    res.range.used = true;
    res.range.measured = *in.range;
    // The beam's axis point at the range is the object's front depth when it falls inside the
    // marked region and agrees with the marks; off the axis the nearest surface may lie deeper
    // by up to range * (1 - cos(half angle)). The narrower search is kept unless it matches
    // clearly worse than the marks' (then the beam met something else).
    const Eigen::Vector3d q = in.ranger_origin + *in.range * in.ranger_axis.normalized();
    const auto qp = in.left_camera.Project(q);
    const double qd = in.left_camera.Depth(q);
    const double beam =
        opt.ranger_accuracy + *in.range * (1 - std::cos(opt.ranger_half_angle_deg * M_PI / 180));
    if (qp && qd > 0 && cv::pointPolygonTest(grown, cv::Point2f(qp->x(), qp->y()), false) >= 0 &&
        std::abs(qd - mark_depth) <= opt.depth_tolerance) {
      const SsdMatch ranged = match_between(std::max(0.5 * qd, qd - beam), qd + beam);
      if (ranged.ok && ranged.rms <= 1.25 * match.rms + 1.0) {
        match = ranged;
        res.range.constrained = true;
      }
    }
  }
  res.ssd_rms = match.rms;
  if (match.rms > opt.max_ssd_rms)
    return finish(Fail(res, Failure::kMatchOverThreshold,
                       "best right-image match within the marks' depth +/- " +
                           Fmt(opt.depth_tolerance, 1) + " differs by " + Fmt(match.rms, 1) +
                           " grey levels RMS (limit " + Fmt(opt.max_ssd_rms, 1) +
                           "): check the marks' depth"));
  const auto x_match = Triangulate(in.left_camera, q_left, in.right_camera, q_left + match.offset);
  if (!x_match)
    return finish(
        Fail(res, Failure::kMatchOverThreshold, "the right-image match does not triangulate"));
  const double depth0 = in.left_camera.Depth(*x_match);
  const cv::Rect right_region =
      cv::Rect(patch.x + static_cast<int>(std::round(match.offset.x())) - pad,
               patch.y + static_cast<int>(std::round(match.offset.y())) - pad,
               patch.width + 2 * pad, patch.height + 2 * pad) &
      image_rect;
  const Gradients grad_right(right, right_region, opt.edge_sigma);

  // 4. Initial model from the left boundary at the matched depth, then the joint fit.
  FitOptions fit;
  fit.search_px = opt.search_px;
  fit.min_gradient = std::max(opt.min_edge_gradient, 0.25 * strongest);
  fit.edge_blur_px = std::hypot(opt.edge_sigma, opt.camera_blur_px);
  fit.outer_iterations = opt.outer_iterations;
  fit.inner_iterations = opt.inner_iterations;
  const std::array<FitView, 2> views = {FitView{&in.left_camera, &grad_left},
                                        FitView{&in.right_camera, &grad_right}};
  Eigen::VectorXd x0;
  std::vector<Eigen::VectorXd> extra_starts;
  OutlineFn outline;
  InnerEdgesFn inner;
  std::vector<cv::Point2f> bpts(boundary.begin(), boundary.end());
  if (in.type == SolidType::kCylinder) {
    const cv::RotatedRect rr = cv::minAreaRect(bpts);
    cv::Point2f c[4];
    rr.points(c);
    Eigen::Vector2d e01(c[1].x - c[0].x, c[1].y - c[0].y), e12(c[2].x - c[1].x, c[2].y - c[1].y);
    if (e01.norm() < e12.norm()) std::swap(e01, e12);
    const Eigen::Vector2d along = e01.normalized(), across = e12.normalized();
    const double half_len = std::max(1.0, 0.5 * e01.norm() - 1.0);
    const double half_width = std::max(0.5, 0.5 * e12.norm() - 1.0);
    const Eigen::Vector2d mid(rr.center.x, rr.center.y);
    const double radius = 0.5 * (AtDepth(in.left_camera, mid + half_width * across, depth0) -
                                 AtDepth(in.left_camera, mid - half_width * across, depth0))
                                    .norm();
    const double axis_depth = depth0 + radius;
    x0.resize(7);
    // The silhouette's ends lie beyond the cap centres by up to the radius, depending on the
    // view; start halfway and let the fit settle it.
    x0.segment<3>(0) =
        AtDepth(in.left_camera, mid - (half_len - 0.5 * half_width) * along, axis_depth);
    x0.segment<3>(3) =
        AtDepth(in.left_camera, mid + (half_len - 0.5 * half_width) * along, axis_depth);
    x0[6] = radius;
    outline = CylinderOutline;
    if (opt.cylinder_inner_edges) inner = CylinderInnerEdges;
    // A pipe lying towards the cameras has its ends at different depths, which one depth for
    // both cannot start from (the fit then settles on a shorter pipe across the view): match
    // each end's patch into the right image on its own and start also from those depths.
    const double lateral = (AtDepth(in.left_camera, mid + half_len * along, depth0) -
                            AtDepth(in.left_camera, mid - half_len * along, depth0))
                               .norm();
    Eigen::VectorXd tilted = x0;
    bool have_tilted = true;
    for (int end = 0; end < 2 && have_tilted; ++end) {
      const Eigen::Vector2d e = mid + (end == 0 ? -1.0 : 1.0) * (half_len - half_width) * along;
      const int side = static_cast<int>(std::ceil(2 * half_width)) + 8;
      const cv::Rect end_patch(static_cast<int>(std::lround(e.x())) - side / 2,
                               static_cast<int>(std::lround(e.y())) - side / 2, side, side);
      const auto ea = in.right_camera.Project(
          AtDepth(in.left_camera, e, std::max(0.5 * d_near, d_near - lateral)));
      const auto eb = in.right_camera.Project(AtDepth(in.left_camera, e, d_far + 2 * lateral));
      const Eigen::Vector2d pc(end_patch.x + 0.5 * (side - 1), end_patch.y + 0.5 * (side - 1));
      if (!ea || !eb) {
        have_tilted = false;
        break;
      }
      const SsdMatch m = MatchAlongSegment(left, right, end_patch & image_rect, *ea - pc, *eb - pc);
      const auto xe = m.ok && m.rms <= opt.max_ssd_rms
                          ? Triangulate(in.left_camera, pc, in.right_camera, pc + m.offset)
                          : std::nullopt;
      if (!xe) {
        have_tilted = false;
        break;
      }
      const Eigen::Vector2d tip =
          mid + (end == 0 ? -1.0 : 1.0) * (half_len - 0.5 * half_width) * along;
      tilted.segment<3>(3 * end) = AtDepth(in.left_camera, tip, in.left_camera.Depth(*xe) + radius);
    }
    if (have_tilted && std::abs(in.left_camera.Depth(tilted.segment<3>(0)) -
                                in.left_camera.Depth(tilted.segment<3>(3))) > radius)
      extra_starts.push_back(tilted);
  } else {
    // A block (3.8.2), started world-axis-aligned: the boundary back-projected onto its front
    // plane gives the two extents across the view; the one along the view starts as their
    // mean. Its yaw is fitted from there (the faces' widths and the edges between them).
    const Eigen::Vector3d view_dir =
        in.left_camera.P().block<1, 3>(2, 0).transpose().normalized() *
        (in.left_camera.P().leftCols<3>().determinant() < 0 ? -1.0 : 1.0);
    int k;
    view_dir.cwiseAbs().maxCoeff(&k);
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e18), hi = -lo, sum = Eigen::Vector3d::Zero();
    for (const auto& p : boundary) {
      const Eigen::Vector3d X = AtDepth(in.left_camera, Eigen::Vector2d(p.x, p.y), depth0);
      lo = lo.cwiseMin(X);
      hi = hi.cwiseMax(X);
      sum += X;
    }
    double across_mean = 0;
    for (int i = 0; i < 3; ++i)
      if (i != k) across_mean += 0.5 * (hi[i] - lo[i]);
    const double front = sum[k] / boundary.size();
    const double back = front + (view_dir[k] > 0 ? 1 : -1) * across_mean;
    lo[k] = std::min(front, back);
    hi[k] = std::max(front, back);
    auto box_start = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, double yaw) {
      Eigen::VectorXd v(7);
      v << 0.5 * (a + b), (b - a).cwiseAbs(), yaw;
      return v;
    };
    x0 = box_start(lo, hi, 0);
    outline = BoxOutline;
    if (opt.box_inner_edges) inner = BoxInnerEdges;
    // The depth along the view is the least seen (a side face's strip, a sliver of the top):
    // also start shallower and deeper, and keep the fit that explains both images best.
    for (const double share : {0.4, 1.8}) {
      const double other = front + (view_dir[k] > 0 ? 1 : -1) * share * across_mean;
      Eigen::Vector3d a = lo, b = hi;
      a[k] = std::min(front, other);
      b[k] = std::max(front, other);
      extra_starts.push_back(box_start(a, b, 0));
    }
  }
  spdlog::debug(
      "locate: marks depth {:.2f}, matched depth {:.2f}, ssd rms {:.1f}, {} boundary px, init [{}]",
      mark_depth, depth0, match.rms, boundary.size(),
      Fmt(x0[0]) + " " + Fmt(x0[1]) + " " + Fmt(x0[2]) + " / " + Fmt(x0[3]) + " " + Fmt(x0[4]) +
          " " + Fmt(x0[5]) + " / " + Fmt(x0[6]));
  // Of several starts, the one that explains both images best after two passes goes on.
  auto score = [](const FitOutcome& o) {
    const int sampled = o.sampled[0] + o.sampled[1];
    const double miss = sampled ? 1.0 - double(o.used[0] + o.used[1]) / sampled : 1.0;
    return o.ok ? o.rms_px[0] + o.rms_px[1] + 2.0 * miss : 1e18;
  };
  auto fit_from = [&](const OutlineFn& outline_fn, const InnerEdgesFn& inner_fn,
                      const std::vector<Eigen::VectorXd>& starts) {
    FitOptions first = fit;
    first.step = Eigen::VectorXd::Constant(starts[0].size(), 1e-4);
    first.outer_iterations =
        starts.size() == 1 ? fit.outer_iterations : std::min(2, fit.outer_iterations);
    FitOutcome best = FitSilhouette(outline_fn, starts[0], views, first, inner_fn);
    for (size_t i = 1; i < starts.size(); ++i) {
      FitOutcome g = FitSilhouette(outline_fn, starts[i], views, first, inner_fn);
      spdlog::debug("locate: another start: score {:.3f} against {:.3f}", score(g), score(best));
      if (score(g) < score(best)) best = std::move(g);
    }
    if (best.ok && first.outer_iterations < fit.outer_iterations) {
      FitOptions rest = first;
      rest.outer_iterations = fit.outer_iterations;
      rest.first_outer = first.outer_iterations;
      best = FitSilhouette(outline_fn, best.params, views, rest, inner_fn);
    }
    return best;
  };
  std::vector<Eigen::VectorXd> starts = {x0};
  starts.insert(starts.end(), extra_starts.begin(), extra_starts.end());
  FitOutcome f;
  if (in.type == SolidType::kCylinder) {
    f = fit_from(outline, inner, starts);
  } else {
    // The thesis's block first: world-aligned (yaw held at 0), which the faces' edges pin
    // down well. Only when its outline misses the edges is the box turned: from several yaws,
    // kept when it explains the images clearly better (a turned box seen nearly face-on can
    // trade yaw against depth and fit about as well, wrongly).
    auto aligned = [&](const Eigen::VectorXd& p) {
      Eigen::VectorXd q(7);
      q << p, 0.0;
      return q;
    };
    std::vector<Eigen::VectorXd> starts6;
    for (const auto& st : starts) starts6.push_back(st.head<6>());
    InnerEdgesFn inner6;
    if (inner)
      inner6 = [&](const Eigen::VectorXd& p, const Eigen::Vector3d& c) {
        return inner(aligned(p), c);
      };
    FitOutcome fa =
        fit_from([&](const Eigen::VectorXd& p) { return outline(aligned(p)); }, inner6, starts6);
    if (fa.ok) {
      fa.params = aligned(fa.params);
      Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(7, 7);
      cov.topLeftCorner<6, 6>() = fa.covariance;
      fa.covariance = cov;
    }
    f = std::move(fa);
    // A fit that flattened the box (no depth left) explained nothing: the turned box's
    // faces drawn as one.
    // A failed fit has no parameters to look at.
    auto solid = [](const FitOutcome& o) {
      if (!o.ok || o.params.size() < 6) return false;
      const Eigen::Vector3d size = o.params.segment<3>(3).cwiseAbs();
      return size.minCoeff() > 0.1 * size.maxCoeff();
    };
    if (!solid(f) || 0.5 * (f.rms_px[0] + f.rms_px[1]) > opt.box_turn_rms_px) {
      std::vector<Eigen::VectorXd> turned;
      const Eigen::VectorXd from = solid(f) ? f.params : x0;
      for (const double yaw_deg : {-36.0, -18.0, 0.0, 18.0, 36.0}) {
        Eigen::VectorXd st = from;
        st[6] = yaw_deg * M_PI / 180;
        turned.push_back(st);
      }
      FitOutcome fo = fit_from(outline, inner, turned);
      spdlog::debug("locate: turned box: score {:.3f} against aligned {:.3f}", score(fo), score(f));
      if (!f.ok || (solid(fo) && (!solid(f) || score(fo) < 0.8 * score(f)))) f = std::move(fo);
    }
  }
  spdlog::debug("locate: fit {} left {}/{} rms {:.3f}, right {}/{} rms {:.3f}, inner {} {}",
                f.ok ? "ok" : f.error, f.used[0], f.sampled[0], f.rms_px[0], f.used[1],
                f.sampled[1], f.rms_px[1], f.inner_used[0], f.inner_used[1]);
  if (in.want_trace) {
    for (const auto& p : hull4) res.trace.marks_left.emplace_back(p.x, p.y);
    res.trace.boundary = boundary;
    res.trace.outline = f.outline;
    res.trace.measured = f.measured;
    res.trace.inlier = f.inlier;
  }
  res.outline_samples = f.used[0] + f.used[1];
  res.rms_left_px = f.rms_px[0];
  res.rms_right_px = f.rms_px[1];
  if (!f.ok) return finish(Fail(res, Failure::kFitFailed, "model fit: " + f.error));

  // 5. Consistency between the views.
  for (int v = 0; v < 2; ++v) {
    const char* name = v == 0 ? "left" : "right";
    const double share = f.sampled[v] ? double(f.used[v]) / f.sampled[v] : 0.0;
    if (share < opt.min_inlier_share)
      return finish(Fail(res, Failure::kLeftRightInconsistent,
                         std::string("only ") + Fmt(100 * share, 0) +
                             "% of the fitted outline has an edge in the " + name +
                             " image: the object is not the same in both views"));
    if (f.rms_px[v] > opt.max_rms_px)
      return finish(Fail(res, Failure::kLeftRightInconsistent,
                         std::string("the fitted outline misses the ") + name +
                             " image's edges by " + Fmt(f.rms_px[v]) + " px RMS (limit " +
                             Fmt(opt.max_rms_px) + ")"));
  }
  const Eigen::VectorXd& x = f.params;
  if (in.type == SolidType::kCylinder) {
    auto outputs = [](const Eigen::VectorXd& p) {
      Eigen::VectorXd o(5);
      o.head<3>() = 0.5 * (p.segment<3>(0) + p.segment<3>(3));
      o[3] = std::abs(p[6]);
      o[4] = (p.segment<3>(3) - p.segment<3>(0)).norm();
      return o;
    };
    const Eigen::VectorXd o = outputs(x), s = Sigmas(outputs, x, f.covariance);
    CylinderResult& c = res.cylinder;
    c.center = o.head<3>();
    c.radius = o[3];
    c.height = o[4];
    c.center_sigma = s.head<3>();
    c.radius_sigma = s[3];
    c.height_sigma = s[4];
    Eigen::Vector3d axis = x.segment<3>(3) - x.segment<3>(0);
    if (c.height < 1e-6 || c.radius < 1e-6)
      return finish(Fail(res, Failure::kFitFailed, "the fitted cylinder has no size"));
    axis.normalize();
    // A stable sign: pointing up, or along +x for a level axis.
    if (axis.z() < -1e-9 || (std::abs(axis.z()) <= 1e-9 && axis.x() < 0)) axis = -axis;
    c.axis = axis;
  } else {
    BoxResult& b = res.box;
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
    const Eigen::VectorXd o = outputs(x), sd = Sigmas(outputs, x, f.covariance);
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
    if (b.size.minCoeff() < 1e-6)
      return finish(Fail(res, Failure::kFitFailed, "the fitted box has no size"));
    double u0 = 1e18, v0 = 1e18, u1 = -1e18, v1 = -1e18;
    for (const auto& p : BoxOutline(x)) {
      const auto px = in.left_camera.Project(p);
      u0 = std::min(u0, px->x());
      v0 = std::min(v0, px->y());
      u1 = std::max(u1, px->x());
      v1 = std::max(v1, px->y());
    }
    b.texture_rect =
        cv::Rect(
            cv::Point(static_cast<int>(std::floor(u0)), static_cast<int>(std::floor(v0))),
            cv::Point(static_cast<int>(std::ceil(u1)) + 1, static_cast<int>(std::ceil(v1)) + 1)) &
        image_rect;
    // The patch for texture mapping (3.8.2), in the left image's own colours, ideal pixels.
    if (!b.texture_rect.empty()) b.texture = Ideal(in.left, in.left_camera)(b.texture_rect).clone();
  }
  if (in.range) CheckRange(in, opt, x, &res.range);
  res.found = true;
  return finish(res);
}

}  // namespace igms::object
