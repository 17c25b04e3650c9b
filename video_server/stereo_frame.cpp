#include "video_server/stereo_frame.h"

#include <chrono>

#include "common/base/clock.h"
#include "video_server/capture_backend.h"

namespace igms::video {

std::string CheckStereoImages(const StereoImages& images) {
  if (images.left.empty() || images.right.empty()) return "an image of the pair is empty";
  for (const cv::Mat* image : {&images.left, &images.right}) {
    if (image->depth() != CV_8U || (image->channels() != 1 && image->channels() != 3)) {
      return "images must be 8-bit grey or 8-bit 3-channel colour";
    }
  }
  if (images.left.size() != images.right.size() || images.left.type() != images.right.type()) {
    return "left is " + std::to_string(images.left.cols) + "x" + std::to_string(images.left.rows) +
           " with " + std::to_string(images.left.channels()) + " channel(s) but right is " +
           std::to_string(images.right.cols) + "x" + std::to_string(images.right.rows) + " with " +
           std::to_string(images.right.channels()) + ": a pair must match";
  }
  return "";
}

CaptureResult CaptureResult::Ok(StereoImages images) {
  CaptureResult result;
  result.images = std::move(images);
  return result;
}

CaptureResult CaptureResult::Error(std::string message) {
  CaptureResult result;
  result.error = std::move(message);
  return result;
}

RenderCapture::RenderCapture(std::string description, RenderFunction render)
    : description_(std::move(description)), render_(std::move(render)) {}

CaptureResult RenderCapture::Capture(const PoseStamp& pose) {
  const int64_t start = UnixNs();
  CaptureResult result = render_(pose);
  if (!result.ok()) {
    if (result.error.empty()) result.error = "the renderer returned no images";
    return result;
  }
  if (std::string error = CheckStereoImages(*result.images); !error.empty()) {
    return CaptureResult::Error("renderer: " + error);
  }
  StereoImages& images = *result.images;
  if (images.left_capture_unix_ns == 0) images.left_capture_unix_ns = start;
  if (images.right_capture_unix_ns == 0) images.right_capture_unix_ns = start;
  images.pose = pose;
  return result;
}

}  // namespace igms::video
