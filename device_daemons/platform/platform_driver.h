// PlatformDriver: the serial side of igms-platformd. Polls the platform's orientation
// (QUERY at options.poll_hz) and publishes the orientation actually reached; sends
// SetOrientation (SPEED when the steps per move change, then SET) and ResetZero, each
// completed when the platform acknowledges it or failed after options.ack_timeout.
//
// Threading: runs on the io_context's thread; the command methods may be called from any
// thread, and `done` is called on the io thread.
#pragma once

#include <boost/asio/steady_timer.hpp>
#include <deque>
#include <functional>
#include <memory>

#include "device_daemons/platform/molly_protocol.h"
#include "device_daemons/serial/device_driver.h"

namespace igms::devices {

struct PlatformDriverOptions {
  SerialLinkOptions link;
  double poll_hz = 50;  // QUERY + ORIENTATION take 11 bytes: at most 87 Hz on the line
  std::chrono::milliseconds ack_timeout{500};
  bool Check(std::string* error) const;
};

PlatformState ToPlatformState(const molly::Message& orientation);  // stamp unset

class PlatformDriver : public DeviceDriver {
 public:
  using ReadingFn = std::function<void(const PlatformState&)>;
  using DoneFn = std::function<void(bool ok, const std::string& message)>;

  PlatformDriver(boost::asio::io_context& io, PlatformDriverOptions options, ReadingFn on_reading,
                 StatusFn on_status = {});

  void SetOrientation(const molly::Ticks& ticks, uint32_t steps_per_move, DoneFn done);
  void ResetZero(DoneFn done);

 private:
  struct Pending {
    uint8_t head;
    DoneFn done;  // only on the last frame of a command
    std::shared_ptr<boost::asio::steady_timer> timer;
  };
  void OnOpened() override;
  void OnSerialBytes(const uint8_t* data, size_t size, int64_t now_ns) override;
  uint64_t bad_frames() const override { return parser_.bad_frames(); }
  uint64_t garbage_bytes() const override { return parser_.garbage_bytes(); }
  void Send(uint8_t head, std::string frame, DoneFn done);
  void FailAll(const std::string& why);

  PlatformDriverOptions options_;
  ReadingFn on_reading_;
  Frame7Parser parser_{molly::BodyLength};
  std::deque<Pending> pending_;
  uint32_t steps_per_move_ = 0;  // last sent; 0 = unknown
};

}  // namespace igms::devices
