#include "video_server/edges.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace igms::video {
namespace {

// atan2 to within 2e-6 rad (an 11th-order odd polynomial for atan on [0, 1], then the
// octant): std::atan2 costs a noticeable share of a 512x480 frame's budget when run on every
// edge pixel, and the directions feed a corner test that needs a degree, not ulps.
float FastAtan2(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  const float big = std::max(ax, ay);
  if (big == 0.0f) return 0.0f;
  const float a = std::min(ax, ay) / big;
  const float s = a * a;
  float r =
      a * (0.99997726f +
           s * (-0.33262347f +
                s * (0.19354346f + s * (-0.11643287f + s * (0.05265332f - s * 0.01172120f)))));
  if (ay > ax) r = 1.57079637f - r;
  if (x < 0.0f) r = 3.14159274f - r;
  return y < 0.0f ? -r : r;
}

}  // namespace

bool EdgeOptions::Check(std::string* error) const {
  if (!std::isfinite(sigma) || sigma < 0.0 || sigma > 50.0) {
    *error = "edge sigma must be in [0, 50] pixels";
    return false;
  }
  if (!std::isfinite(low_threshold) || !std::isfinite(high_threshold) || low_threshold < 0.0 ||
      high_threshold <= 0.0) {
    *error = "edge thresholds must be finite, low >= 0 and high > 0";
    return false;
  }
  if (low_threshold > high_threshold) {
    *error = "the low edge threshold exceeds the high one";
    return false;
  }
  return true;
}

size_t EdgeImage::bytes() const {
  return edges.total() * edges.elemSize() + direction_rad.capacity() * sizeof(float) +
         row_start.capacity() * sizeof(int);
}

EdgeImage DetectEdges(const cv::Mat& image, const EdgeOptions& options) {
  if (std::string problem; !options.Check(&problem)) {
    throw std::invalid_argument(problem);
  }
  EdgeImage result;
  if (image.empty()) return result;
  // Fresh output Mats: assigning the input and writing into it would overwrite the caller's
  // image, which Mat's shared buffers make an easy mistake.
  cv::Mat grey = image;
  if (image.channels() == 3) {
    grey = cv::Mat();
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  }
  cv::Mat smooth = grey;
  if (options.sigma > 0.0) {
    smooth = cv::Mat();
    cv::GaussianBlur(grey, smooth, cv::Size(0, 0), options.sigma, options.sigma,
                     cv::BORDER_REPLICATE);
  }
  // The derivatives are computed once and shared by Canny and the direction of each edge.
  // spatialGradient is the 3x3 Sobel pair in one vectorised pass.
  cv::Mat du, dv;
  cv::spatialGradient(smooth, du, dv, 3, cv::BORDER_REPLICATE);
  cv::Canny(du, dv, result.edges, options.low_threshold, options.high_threshold,
            options.l2_gradient);

  result.row_start.resize(grey.rows + 1);
  result.direction_rad.reserve(static_cast<size_t>(cv::countNonZero(result.edges)));
  for (int v = 0; v < grey.rows; ++v) {
    result.row_start[v] = static_cast<int>(result.direction_rad.size());
    const uint8_t* edge = result.edges.ptr<uint8_t>(v);
    const int16_t* gu = du.ptr<int16_t>(v);
    const int16_t* gv = dv.ptr<int16_t>(v);
    for (int u = 0; u < grey.cols; ++u) {
      if (edge[u]) {
        result.direction_rad.push_back(
            FastAtan2(static_cast<float>(gv[u]), static_cast<float>(gu[u])));
      }
    }
  }
  result.row_start[grey.rows] = static_cast<int>(result.direction_rad.size());
  return result;
}

std::vector<float> DirectionsInRegion(const EdgeImage& edges, const cv::Rect& rect) {
  std::vector<float> out;
  for (int v = rect.y; v < rect.y + rect.height; ++v) {
    const uint8_t* edge = edges.edges.ptr<uint8_t>(v);
    int index = edges.row_start[v];
    for (int u = 0; u < rect.x; ++u) index += edge[u] != 0;
    for (int u = rect.x; u < rect.x + rect.width; ++u) {
      if (edge[u]) out.push_back(edges.direction_rad[index++]);
    }
  }
  return out;
}

}  // namespace igms::video
