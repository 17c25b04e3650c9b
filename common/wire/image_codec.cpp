#include "common/wire/image_codec.h"

#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <vector>

namespace igms::wire {

Result<cv::Rect> ResolveRegion(const PixelRegion& region, cv::Size size) {
  if (region.whole()) return cv::Rect(0, 0, size.width, size.height);
  auto fail = [&](const std::string& why) {
    return ErrorMessage{"region x=" + std::to_string(region.x) + " y=" + std::to_string(region.y) +
                        " width=" + std::to_string(region.width) +
                        " height=" + std::to_string(region.height) + " " + why + " (the image is " +
                        std::to_string(size.width) + "x" + std::to_string(size.height) + ")"};
  };
  if (region.width <= 0 || region.height <= 0) return fail("is empty");
  if (region.x < 0 || region.y < 0) return fail("starts outside the image");
  // 64-bit sums: a huge width plus x must not wrap around into the image.
  if (int64_t{region.x} + region.width > size.width ||
      int64_t{region.y} + region.height > size.height) {
    return fail("reaches outside the image");
  }
  return cv::Rect(region.x, region.y, region.width, region.height);
}

std::string EncodeImage(const cv::Mat& image, ImageEncoding encoding) {
  if (encoding == ImageEncoding::kPng) {
    std::vector<uint8_t> png;
    // Level 1: most of the size reduction of higher levels at a fraction of their time.
    cv::imencode(".png", image, png, {cv::IMWRITE_PNG_COMPRESSION, 1});
    return std::string(png.begin(), png.end());
  }
  const size_t row_bytes = image.cols * image.elemSize();
  std::string raw(row_bytes * image.rows, '\0');
  for (int v = 0; v < image.rows; ++v) {
    std::memcpy(raw.data() + v * row_bytes, image.ptr(v), row_bytes);
  }
  return raw;
}

cv::Mat DecodeImage(const std::string& data, ImageEncoding encoding, int width, int height,
                    int channels) {
  if (encoding == ImageEncoding::kPng) {
    std::vector<uint8_t> bytes(data.begin(), data.end());
    if (bytes.empty()) return {};
    return cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  }
  if (width <= 0 || height <= 0 || (channels != 1 && channels != 3) ||
      data.size() != static_cast<size_t>(width) * height * channels) {
    return {};
  }
  cv::Mat image(height, width, CV_8UC(channels));
  std::memcpy(image.data, data.data(), data.size());
  return image;
}

}  // namespace igms::wire
