#include "video_server/edges.h"

#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace igms::video {

std::string EdgeOptions::Check() const {
  if (!std::isfinite(sigma) || sigma < 0.0 || sigma > 50.0) {
    return "edge sigma must be in [0, 50] pixels";
  }
  if (!std::isfinite(low_threshold) || !std::isfinite(high_threshold) || low_threshold < 0.0 ||
      high_threshold <= 0.0) {
    return "edge thresholds must be finite, low >= 0 and high > 0";
  }
  if (low_threshold > high_threshold) return "the low edge threshold exceeds the high one";
  return "";
}

size_t EdgeImage::bytes() const {
  return edges.total() * edges.elemSize() + direction_rad.capacity() * sizeof(float) +
         row_start.capacity() * sizeof(int);
}

EdgeImage DetectEdges(const cv::Mat& image, const EdgeOptions& options) {
  if (std::string problem = options.Check(); !problem.empty()) {
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
  cv::Mat du, dv;
  cv::Sobel(smooth, du, CV_16S, 1, 0, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
  cv::Sobel(smooth, dv, CV_16S, 0, 1, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
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
            std::atan2(static_cast<float>(gv[u]), static_cast<float>(gu[u])));
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
