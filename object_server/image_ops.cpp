#include "object_server/image_ops.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace igms::object {
namespace {

// Share of the strongest edge along a search line that an outer edge needs to count as the
// silhouette.
constexpr double kOuterFraction = 0.4;

// Catmull-Rom weights for fractional offset t in [0, 1).
inline void CubicWeights(double t, double w[4]) {
  const double t2 = t * t, t3 = t2 * t;
  w[0] = 0.5 * (-t3 + 2 * t2 - t);
  w[1] = 0.5 * (3 * t3 - 5 * t2 + 2);
  w[2] = 0.5 * (-3 * t3 + 4 * t2 + t);
  w[3] = 0.5 * (t3 - t2);
}

}  // namespace

Gradients::Gradients(const cv::Mat& gray, cv::Rect region, double sigma) {
  const int border = static_cast<int>(std::ceil(3 * sigma)) + 4;
  region_ = cv::Rect(region.x - border, region.y - border, region.width + 2 * border,
                     region.height + 2 * border) &
            cv::Rect(0, 0, gray.cols, gray.rows);
  if (region_.empty()) return;
  cv::Mat f;
  gray(region_).convertTo(f, CV_32F);
  if (sigma > 0) cv::GaussianBlur(f, f, cv::Size(0, 0), sigma, sigma, cv::BORDER_REPLICATE);
  cv::Mat gx, gy;
  cv::Sobel(f, gx, CV_32F, 1, 0, 3, 1.0 / 8, 0, cv::BORDER_REPLICATE);
  cv::Sobel(f, gy, CV_32F, 0, 1, 3, 1.0 / 8, 0, cv::BORDER_REPLICATE);
  cv::merge(std::vector<cv::Mat>{gx, gy}, g_);
}

Eigen::Vector2d Gradients::At(const Eigen::Vector2d& p) const {
  const double x = p.x() - region_.x, y = p.y() - region_.y;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  if (x0 < 1 || y0 < 1 || x0 + 2 >= g_.cols || y0 + 2 >= g_.rows) return {0, 0};
  double wx[4], wy[4];
  CubicWeights(x - x0, wx);
  CubicWeights(y - y0, wy);
  double sx = 0, sy = 0;
  for (int j = 0; j < 4; ++j) {
    const float* row =
        g_.ptr<float>(y0 - 1 + j) + 2 * std::ptrdiff_t{x0 - 1};  // gx, gy interleaved
    double ax = 0, ay = 0;
    for (std::ptrdiff_t i = 0; i < 4; ++i) {
      ax += wx[i] * row[2 * i];
      ay += wx[i] * row[2 * i + 1];
    }
    sx += wy[j] * ax;
    sy += wy[j] * ay;
  }
  return {sx, sy};
}

float Gradients::MagnitudeAt(int x, int y) const {
  x -= region_.x;
  y -= region_.y;
  if (x < 0 || y < 0 || x >= g_.cols || y >= g_.rows) return 0;
  const cv::Vec2f& g = g_.at<cv::Vec2f>(y, x);
  return std::hypot(g[0], g[1]);
}

std::vector<cv::Point> StrongEdgePixels(const Gradients& grad,
                                        const std::vector<cv::Point2f>& polygon,
                                        const cv::Mat& edges, double fraction, double min_gradient,
                                        double* strongest, double quantile) {
  const cv::Rect box = cv::boundingRect(polygon) & grad.region();
  std::vector<std::pair<cv::Point, float>> inside;
  float max_mag = 0;
  if (box.empty()) {
    if (strongest) *strongest = 0;
    return {};
  }
  // The polygon drawn once into a mask of the box (vertices to 1/16 px), not tested per pixel.
  cv::Mat mask = cv::Mat::zeros(box.size(), CV_8U);
  {
    constexpr int kShift = 4;
    std::vector<cv::Point> vertices;
    vertices.reserve(polygon.size());
    for (const auto& p : polygon)
      vertices.emplace_back(cvRound((p.x - static_cast<float>(box.x)) * (1 << kShift)),
                            cvRound((p.y - static_cast<float>(box.y)) * (1 << kShift)));
    cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{vertices}, 255, cv::LINE_8, kShift);
  }
  for (int y = box.y; y < box.y + box.height; ++y) {
    const uint8_t* in_polygon = mask.ptr<uint8_t>(y - box.y);
    for (int x = box.x; x < box.x + box.width; ++x) {
      if (!in_polygon[x - box.x]) continue;
      if (!edges.empty() && (y >= edges.rows || x >= edges.cols || edges.at<uint8_t>(y, x) == 0))
        continue;
      const float m = grad.MagnitudeAt(x, y);
      max_mag = std::max(max_mag, m);
      inside.push_back({{x, y}, m});
    }
  }
  if (quantile < 1) {
    constexpr size_t kMinEdgePixels = 20;
    std::vector<float> edge;
    for (const auto& [p, m] : inside)
      if (m >= min_gradient) edge.push_back(m);
    if (edge.size() >= kMinEdgePixels) {
      const auto k = std::min(edge.size() - 1,
                              static_cast<size_t>(quantile * static_cast<double>(edge.size())));
      std::nth_element(edge.begin(), edge.begin() + static_cast<std::ptrdiff_t>(k), edge.end());
      max_mag = edge[k];
    }
  }
  if (strongest) *strongest = max_mag;
  const double threshold = std::max(min_gradient, fraction * max_mag);
  std::vector<cv::Point> out;
  for (const auto& [p, m] : inside)
    if (m >= threshold) out.push_back(p);
  return out;
}

namespace {

enum class Peak { kOutermost, kNearest };

bool EdgePeak(const Gradients& grad, const Eigen::Vector2d& p, const Eigen::Vector2d& n,
              double range, double min_gradient, Peak which, double* s) {
  // Coarse scan every half pixel, then a parabola through the best sample and its neighbours.
  const double step = 0.5;
  constexpr int kMaxCount = 64;  // a 32 px search either side
  const int count = std::min(kMaxCount, static_cast<int>(std::floor(range / step)));
  double best = -1;
  int best_i = 0;
  std::array<double, 2 * kMaxCount + 1> g;
  for (int i = -count; i <= count; ++i) {
    const double v = std::abs(grad.At(p + i * step * n).dot(n));
    g[i + count] = v;
    if (v > best) {
      best = v;
      best_i = i;
    }
  }
  if (best < min_gradient) return false;
  // A silhouette is the outermost strong edge: inner edges (a cylinder's cap rim, a box's face
  // boundary) can be stronger, so take the outermost local maximum that is at least
  // outer_fraction of the strongest, not the strongest itself.
  const double floor_value = std::max(min_gradient, kOuterFraction * best);
  auto is_peak = [&](int i) {
    const double v = g[i + count];
    return v >= floor_value && v >= g[i + count - 1] && v >= g[i + count + 1];
  };
  if (which == Peak::kOutermost) {
    for (int i = count - 1; i > -count; --i)
      if (is_peak(i)) {
        best_i = i;
        break;
      }
  } else {
    // An edge inside the silhouette: the peak nearest the prediction, either side.
    for (int d = 0; d < count; ++d)
      if (is_peak(d)) {
        best_i = d;
        break;
      } else if (d > 0 && is_peak(-d)) {
        best_i = -d;
        break;
      }
  }
  if (best_i == -count || best_i == count) return false;
  const double a = g[best_i + count - 1], b = g[best_i + count], c = g[best_i + count + 1];
  const double denom = a - 2 * b + c;
  double frac = denom < 0 ? 0.5 * (a - c) / denom : 0.0;
  frac = std::clamp(frac, -0.5, 0.5);
  double s0 = (best_i + frac) * step;
  // Refine once more on a finer bracket, where the parabola fits the smooth peak better.
  const double h = 0.2;
  const double fa = std::abs(grad.At(p + (s0 - h) * n).dot(n));
  const double fb = std::abs(grad.At(p + s0 * n).dot(n));
  const double fc = std::abs(grad.At(p + (s0 + h) * n).dot(n));
  const double d2 = fa - 2 * fb + fc;
  if (d2 < 0) s0 += std::clamp(0.5 * (fa - fc) / d2, -1.0, 1.0) * h;
  *s = s0;
  return true;
}

}  // namespace

double GreyAt(const cv::Mat& image, const Eigen::Vector2d& p) {
  const double x = std::clamp(p.x(), 0.0, image.cols - 1.001);
  const double y = std::clamp(p.y(), 0.0, image.rows - 1.001);
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const double fx = x - x0, fy = y - y0;
  const auto at = [&](int yy, int xx) { return static_cast<double>(image.at<uint8_t>(yy, xx)); };
  return (1 - fy) * ((1 - fx) * at(y0, x0) + fx * at(y0, x0 + 1)) +
         fy * ((1 - fx) * at(y0 + 1, x0) + fx * at(y0 + 1, x0 + 1));
}

double NoiseSigma(const cv::Mat& image, cv::Rect box) {
  box &= cv::Rect(0, 0, image.cols, image.rows);
  std::vector<int> diffs;
  diffs.reserve(static_cast<size_t>(box.area()));
  for (int y = box.y; y < box.y + box.height; ++y) {
    const uint8_t* row = image.ptr<uint8_t>(y);
    for (int x = box.x; x + 1 < box.x + box.width; ++x)
      diffs.push_back(std::abs(row[x + 1] - row[x]));
  }
  if (diffs.empty()) return 0;
  const auto mid = diffs.begin() + static_cast<std::ptrdiff_t>(diffs.size() / 2);
  std::nth_element(diffs.begin(), mid, diffs.end());
  return 1.4826 * *mid / std::sqrt(2.0);
}

bool EdgeAlongNormal(const Gradients& grad, const Eigen::Vector2d& p, const Eigen::Vector2d& n,
                     double range, double min_gradient, double* s) {
  return EdgePeak(grad, p, n, range, min_gradient, Peak::kOutermost, s);
}

bool EdgeNearPoint(const Gradients& grad, const Eigen::Vector2d& p, const Eigen::Vector2d& n,
                   double range, double min_gradient, double* s) {
  return EdgePeak(grad, p, n, range, min_gradient, Peak::kNearest, s);
}

SsdMatch MatchAlongSegment(const cv::Mat& left, const cv::Mat& right, cv::Rect patch,
                           const Eigen::Vector2d& offset_a, const Eigen::Vector2d& offset_b,
                           const cv::Mat& mask) {
  SsdMatch result;
  const cv::Rect whole = patch;
  patch &= cv::Rect(0, 0, left.cols, left.rows);
  if (patch.area() < 9) return result;
  cv::Mat used;                 // the mask's part over the patch kept in the left image
  int compared = patch.area();  // pixels compared
  if (!mask.empty()) {
    if (mask.size() != whole.size()) return result;
    used = mask(cv::Rect(patch.tl() - whole.tl(), patch.size()));
    compared = cv::countNonZero(used);
    if (compared < 9) return result;
  }
  // Only the part of the segment where the shifted patch lies inside the right image (with a
  // pixel to spare for the interpolation): an object near the image's edge keeps the rest.
  Eigen::Vector2d a = offset_a, b = offset_b;
  {
    double t0 = 0, t1 = 1;
    const Eigen::Vector2d d = b - a;
    const double lo_x = 1 - patch.x, hi_x = right.cols - 2 - (patch.x + patch.width - 1);
    const double lo_y = 1 - patch.y, hi_y = right.rows - 2 - (patch.y + patch.height - 1);
    auto clip = [&](double p0, double dp, double lo, double hi) {
      if (std::abs(dp) < 1e-12) {
        if (p0 < lo || p0 > hi) t1 = -1;
        return;
      }
      double ta = (lo - p0) / dp, tb = (hi - p0) / dp;
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    };
    clip(a.x(), d.x(), lo_x, hi_x);
    clip(a.y(), d.y(), lo_y, hi_y);
    if (t0 > t1) return result;
    b = offset_a + t1 * d;
    a = offset_a + t0 * d;
  }
  const Eigen::Vector2d& offset_lo = a;
  const Eigen::Vector2d& offset_hi = b;
  const Eigen::Vector2d lo = offset_lo.cwiseMin(offset_hi), hi = offset_lo.cwiseMax(offset_hi);
  const int ox0 = static_cast<int>(std::floor(lo.x())) - 1,
            oy0 = static_cast<int>(std::floor(lo.y())) - 1;
  const int ox1 = static_cast<int>(std::ceil(hi.x())) + 1,
            oy1 = static_cast<int>(std::ceil(hi.y())) + 1;
  const cv::Rect search(patch.x + ox0, patch.y + oy0, patch.width + ox1 - ox0,
                        patch.height + oy1 - oy0);
  if ((search & cv::Rect(0, 0, right.cols, right.rows)) != search) return result;
  cv::Mat map, ncc;
  cv::matchTemplate(right(search), left(patch), map, cv::TM_SQDIFF, used);
  cv::matchTemplate(right(search), left(patch), ncc, cv::TM_CCOEFF_NORMED, used);
  // map(y, x) is the SSD at offset (ox0 + x, oy0 + y); read it along the segment.
  const double length = (offset_hi - offset_lo).norm();
  const int steps = std::max(2, static_cast<int>(std::ceil(length / 0.25)));
  auto ssd_at = [&](const Eigen::Vector2d& o, const cv::Mat& map) {
    const double x = o.x() - ox0, y = o.y() - oy0;
    const int x0 = std::clamp(static_cast<int>(std::floor(x)), 0, map.cols - 2);
    const int y0 = std::clamp(static_cast<int>(std::floor(y)), 0, map.rows - 2);
    const double fx = std::clamp(x - x0, 0.0, 1.0), fy = std::clamp(y - y0, 0.0, 1.0);
    return (1 - fy) * ((1 - fx) * map.at<float>(y0, x0) + fx * map.at<float>(y0, x0 + 1)) +
           fy * ((1 - fx) * map.at<float>(y0 + 1, x0) + fx * map.at<float>(y0 + 1, x0 + 1));
  };
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= steps; ++i) {
    const Eigen::Vector2d o = offset_lo + (offset_hi - offset_lo) * (double(i) / steps);
    const double v = ssd_at(o, map);
    if (v < best) {
      best = v;
      result.offset = o;
    }
  }
  result.ok = true;
  result.rms = std::sqrt(std::max(0.0, best) / compared);
  // A flat patch (no contrast at all) has no defined correlation: OpenCV gives 0 or 1; a
  // patch without texture matches nothing.
  result.zncc = std::clamp(ssd_at(result.offset, ncc), -1.0, 1.0);
  return result;
}

}  // namespace igms::object
