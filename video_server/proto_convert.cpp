#include "video_server/proto_convert.h"

namespace igms::video {

PixelRegion FromProto(const igms::video::Region& region) {
  return {region.x(), region.y(), region.width(), region.height()};
}

void ToProto(const PoseStamp& pose, igms::video::PlatformPose* out) {
  out->clear_joints_rad();
  for (double joint : pose.joints_rad) out->add_joints_rad(joint);
  out->set_from_platform(pose.from_platform);
  out->set_time_unix_ns(pose.time_unix_ns);
}

void ToProto(const Overlay& settings, igms::video::OverlaySettings* out) {
  out->set_u_offset_px(settings.u_offset_px);
  out->set_v_offset_px(settings.v_offset_px);
  out->set_key_level(settings.key_level);
}

Overlay FromProto(const igms::video::OverlaySettings& settings) {
  return {settings.u_offset_px(), settings.v_offset_px(), settings.key_level()};
}

void ToProto(const EdgeOptions& options, EdgeParameters* out) {
  out->set_sigma_px(options.sigma);
  out->set_low_threshold(options.low_threshold);
  out->set_high_threshold(options.high_threshold);
  out->set_l2_gradient(options.l2_gradient);
}

ImageEncoding FromProto(igms::video::Encoding encoding, ImageEncoding fallback) {
  switch (encoding) {
    case igms::video::RAW:
      return ImageEncoding::kRaw;
    case igms::video::PNG:
      return ImageEncoding::kPng;
    default:
      return fallback;
  }
}

void EncodeRegion(const cv::Mat& image, const cv::Rect& rect, ImageEncoding encoding, Image* out) {
  out->set_width(rect.width);
  out->set_height(rect.height);
  out->set_channels(image.channels());
  out->set_encoding(encoding == ImageEncoding::kPng ? igms::video::PNG : igms::video::RAW);
  *out->mutable_data() = EncodeImage(image(rect), encoding);
  out->mutable_region()->set_x(rect.x);
  out->mutable_region()->set_y(rect.y);
  out->mutable_region()->set_width(rect.width);
  out->mutable_region()->set_height(rect.height);
}

cv::Mat DecodeProtoImage(const Image& image) {
  const ImageEncoding encoding = image.encoding() == igms::video::PNG ? ImageEncoding::kPng : ImageEncoding::kRaw;
  cv::Mat decoded =
      DecodeImage(image.data(), encoding, image.width(), image.height(), image.channels());
  if (decoded.empty() || decoded.cols != image.width() || decoded.rows != image.height() ||
      decoded.channels() != image.channels()) {
    return {};
  }
  return decoded;
}

}  // namespace igms::video
