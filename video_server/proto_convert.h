// Conversions between the library's types and the igms.video messages.
#pragma once

#include "igms/video.pb.h"
#include "video_server/edges.h"
#include "video_server/image_codec.h"
#include "video_server/overlay_settings.h"
#include "video_server/stereo_frame.h"

namespace igms::video {

PixelRegion FromProto(const igms::video::Region& region);
void ToProto(const PoseStamp& pose, igms::video::PlatformPose* out);
void ToProto(const Overlay& settings, igms::video::OverlaySettings* out);
Overlay FromProto(const igms::video::OverlaySettings& settings);
void ToProto(const EdgeOptions& options, EdgeParameters* out);
// ENCODING_UNSPECIFIED gives `fallback`.
ImageEncoding FromProto(igms::video::Encoding encoding, ImageEncoding fallback);

// Fills `out` with `rect` of `image`, encoded.
void EncodeRegion(const cv::Mat& image, const cv::Rect& rect, ImageEncoding encoding, Image* out);
// Decodes an Image message; an empty Mat when it does not decode to its stated size.
cv::Mat DecodeProtoImage(const Image& image);

}  // namespace igms::video
