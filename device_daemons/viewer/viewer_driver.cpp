#include "device_daemons/viewer/viewer_driver.h"

#include <algorithm>

namespace igms::devices {

bool ViewerDriverOptions::Check(std::string* error) const {
  if (!link.Check(error)) return false;
  if (!(poll_hz > 0)) {
    *error = "viewer poll rate must be positive";
    return false;
  }
  return true;
}

ViewerState ToViewerState(const boom::Pose& p) {
  ViewerState s;
  s.set_x_m(p.x_m);
  s.set_y_m(p.y_m);
  s.set_z_m(p.z_m);
  s.set_yaw_deg(p.yaw_deg);
  s.set_pitch_deg(p.pitch_deg);
  s.set_roll_deg(p.roll_deg);
  s.set_button_left(p.left);
  s.set_button_right(p.right);
  s.set_device_sequence(p.counter);
  return s;
}

ViewerDriver::ViewerDriver(boost::asio::io_context& io, ViewerDriverOptions options,
                           ReadingFn on_reading, StatusFn on_status)
    : DeviceDriver(io, options.link, "viewer", std::move(on_status)),
      options_(std::move(options)),
      on_reading_(std::move(on_reading)) {
  options_.poll_hz = std::min(options_.poll_hz, boom::kMaxRateHz);
}

void ViewerDriver::OnOpened() {
  parser_.Reset();
  if (options_.stream) {
    Write(std::string(1, boom::kStream));
  } else {
    StartPolling(options_.poll_hz, std::string(1, boom::kPoll));
  }
}

void ViewerDriver::OnSerialBytes(const uint8_t* data, size_t size, int64_t now_ns) {
  for (size_t i = 0; i < size; ++i) {
    if (parser_.Feed(data[i]) != ParseResult::kGood) continue;
    const auto pose = boom::DecodeReport(parser_.frame());
    if (!pose) continue;
    ViewerState state = ToViewerState(*pose);
    StampReading(state.mutable_stamp(), now_ns);
    on_reading_(state);
  }
}

}  // namespace igms::devices
