// ViewerDriver: the serial side of igms-viewerd. Polls the viewer ('P' at options.poll_hz,
// each request a cycle ahead of its reading, thesis 2.1.2) or has it stream ('S'), parses
// boom_protocol.h reports and publishes time-stamped ViewerStates.
#pragma once

#include <functional>

#include "device_daemons/serial/device_driver.h"
#include "device_daemons/serial/frame7.h"
#include "device_daemons/viewer/boom_protocol.h"

namespace igms::devices {

struct ViewerDriverOptions {
  SerialLinkOptions link;
  double poll_hz = boom::kMaxRateHz;  // clamped to 70 Hz
  bool stream = false;
  bool Check(std::string* error) const;
};

ViewerState ToViewerState(const boom::Pose& pose);  // stamp unset

class ViewerDriver : public DeviceDriver {
 public:
  using ReadingFn = std::function<void(const ViewerState&)>;
  ViewerDriver(boost::asio::io_context& io, ViewerDriverOptions options, ReadingFn on_reading,
               StatusFn on_status = {});

 private:
  void OnOpened() override;
  void OnSerialBytes(const uint8_t* data, size_t size, int64_t now_ns) override;
  uint64_t bad_frames() const override { return parser_.bad_frames(); }
  uint64_t garbage_bytes() const override { return parser_.garbage_bytes(); }

  ViewerDriverOptions options_;
  ReadingFn on_reading_;
  Frame7Parser parser_{boom::BodyLength};
};

}  // namespace igms::devices
