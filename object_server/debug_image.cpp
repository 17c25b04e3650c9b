#include "object_server/debug_image.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <string>

namespace igms::object {
namespace {

const cv::Scalar kYellow(0, 230, 255), kMagenta(255, 0, 255), kBlue(255, 140, 0), kGreen(0, 220, 0),
    kRed(0, 0, 255), kWhite(255, 255, 255);

cv::Mat Bgr(const cv::Mat& img) {
  cv::Mat out;
  if (img.channels() == 1)
    cv::cvtColor(img, out, cv::COLOR_GRAY2BGR);
  else
    out = img.clone();
  return out;
}

// Image point p drawn into a view showing `region` at `scale`; pixel centres at integers.
cv::Point2f Map(const Eigen::Vector2d& p, const cv::Rect& region, double scale) {
  return {static_cast<float>((p.x() - region.x + 0.5) * scale - 0.5),
          static_cast<float>((p.y() - region.y + 0.5) * scale - 0.5)};
}

void Polygon(cv::Mat& img, const std::vector<Eigen::Vector2d>& pts, const cv::Rect& region,
             double scale, const cv::Scalar& colour) {
  if (pts.size() < 2) return;
  constexpr int kShift = 4;  // sub-pixel drawing
  std::vector<cv::Point> poly;
  for (const auto& p : pts) {
    const cv::Point2f q = Map(p, region, scale);
    poly.emplace_back(std::lround(q.x * (1 << kShift)), std::lround(q.y * (1 << kShift)));
  }
  cv::polylines(img, poly, true, colour, 1, cv::LINE_AA, kShift);
}

// The object's neighbourhood in one view: the outline's and marks' bounding box, grown.
cv::Rect Neighbourhood(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b,
                       const cv::Size& size) {
  double u0 = 1e18, v0 = 1e18, u1 = -1e18, v1 = -1e18;
  for (const auto* pts : {&a, &b})
    for (const auto& p : *pts) {
      u0 = std::min(u0, p.x());
      v0 = std::min(v0, p.y());
      u1 = std::max(u1, p.x());
      v1 = std::max(v1, p.y());
    }
  if (u0 > u1) return cv::Rect(0, 0, size.width, size.height);
  const int pad = 8;
  const cv::Rect r(static_cast<int>(std::floor(u0)) - pad, static_cast<int>(std::floor(v0)) - pad,
                   static_cast<int>(std::ceil(u1 - u0)) + 2 * pad + 1,
                   static_cast<int>(std::ceil(v1 - v0)) + 2 * pad + 1);
  const cv::Rect clipped = r & cv::Rect(0, 0, size.width, size.height);
  return clipped.empty() ? cv::Rect(0, 0, size.width, size.height) : clipped;
}

cv::Mat Zoom(const cv::Mat& bgr, const cv::Rect& region, const cv::Size& box, double* scale) {
  *scale = std::clamp(
      std::floor(std::min(double(box.width) / region.width, double(box.height) / region.height)),
      1.0, 6.0);
  cv::Mat out;
  cv::resize(bgr(region), out, cv::Size(), *scale, *scale, cv::INTER_NEAREST);
  return out;
}

std::string Caption(const LocateResult& r) {
  char buf[512];
  if (!r.found) {
    std::snprintf(buf, sizeof buf, "NOT FOUND (%s): %s", FailureName(r.reason), r.detail.c_str());
  } else if (r.type == SolidType::kCylinder) {
    const auto& c = r.cylinder;
    std::snprintf(buf, sizeof buf,
                  "cylinder: centre (%.2f %.2f %.2f) axis (%.2f %.2f %.2f) radius %.3f height "
                  "%.3f; rms %.2f/%.2f px",
                  c.center.x(), c.center.y(), c.center.z(), c.axis.x(), c.axis.y(), c.axis.z(),
                  c.radius, c.height, r.rms_left_px, r.rms_right_px);
  } else {
    const Eigen::Vector3d s = r.box.size, c = r.box.center;
    std::snprintf(buf, sizeof buf,
                  "box: centre (%.2f %.2f %.2f) size %.3f x %.3f x %.3f yaw %.1f deg; rms "
                  "%.2f/%.2f px",
                  c.x(), c.y(), c.z(), s.x(), s.y(), s.z(), r.box.yaw_deg, r.rms_left_px,
                  r.rms_right_px);
  }
  return buf;
}

}  // namespace

cv::Mat DebugImage(const LocateInput& in, const LocateResult& r) {
  const std::array<cv::Mat, 2> views = {Bgr(in.left), Bgr(in.right)};
  const int w = std::max(views[0].cols, views[1].cols), h = std::max(views[0].rows, views[1].rows);
  const int caption_h = 44, zoom_h = std::max(h, 360);
  cv::Mat canvas(caption_h + h + zoom_h, 2 * w, CV_8UC3, cv::Scalar(32, 32, 32));
  for (int v = 0; v < 2; ++v) {
    const cv::Rect whole(0, 0, views[v].cols, views[v].rows);
    cv::Mat full = views[v].clone();
    const auto& marks = v == 0 ? r.trace.marks_left : std::vector<Eigen::Vector2d>{};
    Polygon(full, marks, whole, 1, kYellow);
    Polygon(full, r.trace.outline[v], whole, 1, kMagenta);
    full.copyTo(canvas(cv::Rect(v * w, caption_h, full.cols, full.rows)));

    const cv::Rect region = Neighbourhood(r.trace.outline[v], marks, views[v].size());
    double scale = 1;
    cv::Mat zoom = Zoom(views[v], region, cv::Size(w, zoom_h), &scale);
    if (v == 0)
      for (const cv::Point& p : r.trace.boundary) {
        const cv::Point2f q = Map(Eigen::Vector2d(p.x, p.y), region, scale);
        cv::circle(zoom, q, std::max(1, static_cast<int>(scale / 3)), kBlue, cv::FILLED);
      }
    Polygon(zoom, marks, region, scale, kYellow);
    Polygon(zoom, r.trace.outline[v], region, scale, kMagenta);
    for (size_t i = 0; i < r.trace.measured[v].size(); ++i) {
      const cv::Point2f q = Map(r.trace.measured[v][i], region, scale);
      const cv::Scalar colour = r.trace.inlier[v][i] ? kGreen : kRed;
      cv::drawMarker(zoom, q, colour, cv::MARKER_CROSS, std::max(3, static_cast<int>(scale)), 1);
    }
    const cv::Rect place(v * w, caption_h + h, std::min(zoom.cols, w), std::min(zoom.rows, zoom_h));
    zoom(cv::Rect(0, 0, place.width, place.height)).copyTo(canvas(place));
    char label[128];
    std::snprintf(label, sizeof label, "%s x%.0f (u %d..%d, v %d..%d)", v == 0 ? "left" : "right",
                  scale, region.x, region.x + region.width - 1, region.y,
                  region.y + region.height - 1);
    cv::putText(canvas, label, cv::Point(v * w + 6, caption_h + h + 16), cv::FONT_HERSHEY_SIMPLEX,
                0.45, kWhite, 1, cv::LINE_AA);
  }
  const std::string caption = Caption(r);
  cv::putText(canvas, caption.substr(0, 110), cv::Point(6, 17), cv::FONT_HERSHEY_SIMPLEX, 0.45,
              kWhite, 1, cv::LINE_AA);
  const std::string legend =
      "yellow: marks  blue: strong edges  green/red: measured edge points used/rejected  magenta: "
      "fitted outline";
  cv::putText(canvas, caption.size() > 110 ? caption.substr(110, 110) : legend, cv::Point(6, 36),
              cv::FONT_HERSHEY_SIMPLEX, 0.45, kWhite, 1, cv::LINE_AA);
  return canvas;
}

}  // namespace igms::object
