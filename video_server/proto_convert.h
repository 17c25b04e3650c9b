// Conversions between the video server's own types and the igms.video messages. The image
// messages themselves are common/wire's (image_message.h), shared with the server's clients.
#pragma once

#include "common/wire/image_message.h"
#include "igms/video.pb.h"
#include "video_server/edges.h"
#include "video_server/overlay_settings.h"
#include "video_server/stereo_frame.h"

namespace igms::video {

void ToProto(const PoseStamp& pose, igms::video::PlatformPose* out);
void ToProto(const Overlay& settings, igms::video::OverlaySettings* out);
Overlay FromProto(const igms::video::OverlaySettings& settings);
void ToProto(const EdgeOptions& options, EdgeParameters* out);

}  // namespace igms::video
