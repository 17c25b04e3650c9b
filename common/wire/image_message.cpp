#include "common/wire/image_message.h"

namespace igms::wire {

PixelRegion RegionFromProto(const igms::video::Region& region) {
  return {region.x(), region.y(), region.width(), region.height()};
}

ImageEncoding EncodingFromProto(igms::video::Encoding encoding, ImageEncoding fallback) {
  switch (encoding) {
    case igms::video::RAW:
      return ImageEncoding::kRaw;
    case igms::video::PNG:
      return ImageEncoding::kPng;
    default:
      return fallback;
  }
}

void EncodeRegion(const cv::Mat& image, const cv::Rect& rect, ImageEncoding encoding,
                  igms::video::Image* out) {
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

cv::Mat DecodeProtoImage(const igms::video::Image& image) {
  const ImageEncoding encoding =
      image.encoding() == igms::video::PNG ? ImageEncoding::kPng : ImageEncoding::kRaw;
  cv::Mat decoded =
      DecodeImage(image.data(), encoding, image.width(), image.height(), image.channels());
  if (decoded.empty() || decoded.cols != image.width() || decoded.rows != image.height() ||
      decoded.channels() != image.channels()) {
    return {};
  }
  return decoded;
}

}  // namespace igms::wire
