// The igms.video image messages as OpenCV images: what the video server sends and every
// client of it (the object server, tests, tools) decodes, so that no client links the video
// server to read one image.
#pragma once

#include <opencv2/core.hpp>

#include "common/wire/image_codec.h"
#include "igms/video.pb.h"

namespace igms::wire {

PixelRegion RegionFromProto(const igms::video::Region& region);
// ENCODING_UNSPECIFIED gives `fallback`.
ImageEncoding EncodingFromProto(igms::video::Encoding encoding, ImageEncoding fallback);

// Fills `out` with `rect` of `image`, encoded.
void EncodeRegion(const cv::Mat& image, const cv::Rect& rect, ImageEncoding encoding,
                  igms::video::Image* out);
// Decodes an Image message; an empty Mat when it does not decode to its stated size.
cv::Mat DecodeProtoImage(const igms::video::Image& image);

}  // namespace igms::wire
