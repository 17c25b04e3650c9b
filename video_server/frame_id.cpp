#include "video_server/frame_id.h"

#include "common/base/clock.h"
#include "video_server/stereo_frame.h"

namespace igms::video {

FrameIdSource::FrameIdSource(uint64_t base)
    : first_(base != 0 ? base : static_cast<uint64_t>(UnixNs() / 1000)), next_(first_) {}

}  // namespace igms::video
