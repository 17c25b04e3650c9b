#include "video_server/proto_convert.h"

namespace igms::video {

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

}  // namespace igms::video
