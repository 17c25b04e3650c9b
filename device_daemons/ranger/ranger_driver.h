// RangerDriver: the serial side of igms-rangerd. The ranger is polled on request (thesis
// 2.1.5): Range() writes 'R' and completes with the answer, or fails after
// options.timeout; with options.poll_hz > 0 it also ranges continuously (at most 6 Hz;
// at 6 Hz each answer triggers the next request).
// Every answer is published as a RangerState. On every (re)open one range is taken to
// check the device answers. Threading as DeviceDriver.
#pragma once

#include <boost/asio/steady_timer.hpp>
#include <deque>
#include <functional>
#include <memory>

#include "device_daemons/ranger/udm_protocol.h"
#include "device_daemons/serial/device_driver.h"

namespace igms::devices {

struct RangerDriverOptions {
  SerialLinkOptions link;
  double poll_hz = 0;  // 0: only on request
  std::chrono::milliseconds timeout{600};
  bool Check(std::string* error) const;
};

class RangerDriver : public DeviceDriver {
 public:
  using ReadingFn = std::function<void(const RangerState&)>;
  using DoneFn = std::function<void(bool ok, const RangerState& state, const std::string& message)>;

  RangerDriver(boost::asio::io_context& io, RangerDriverOptions options, ReadingFn on_reading,
               StatusFn on_status = {});
  void Range(DoneFn done);

 private:
  void OnOpened() override;
  void OnSerialBytes(const uint8_t* data, size_t size, int64_t now_ns) override;
  uint64_t bad_frames() const override { return parser_.bad_frames(); }
  uint64_t garbage_bytes() const override { return parser_.garbage_bytes(); }

  RangerDriverOptions options_;
  ReadingFn on_reading_;
  Frame7Parser parser_{udm::BodyLength};
  struct Waiter {
    DoneFn done;
    std::shared_ptr<boost::asio::steady_timer> timer;
  };
  std::deque<Waiter> waiters_;
};

}  // namespace igms::devices
