#include "device_daemons/ranger/ranger_driver.h"

#include <boost/asio/post.hpp>

namespace igms::devices {

bool RangerDriverOptions::Check(std::string* error) const {
  if (!link.Check(error)) return false;
  if (!(poll_hz >= 0) || poll_hz > udm::kMaxRateHz) {
    *error = "ranger poll rate must be in [0, 6] Hz";
    return false;
  }
  return true;
}

RangerDriver::RangerDriver(boost::asio::io_context& io, RangerDriverOptions options,
                           ReadingFn on_reading, StatusFn on_status)
    : DeviceDriver(
          io,
          [&] {
            SerialLinkOptions link = options.link;
            // A ranger asked only on request is silent in between: that is no fault.
            if (options.poll_hz == 0) link.silence_timeout = std::chrono::hours(24);
            return link;
          }(),
          "ranger", std::move(on_status)),
      options_(std::move(options)),
      on_reading_(std::move(on_reading)) {}

void RangerDriver::OnOpened() {
  parser_.Reset();
  if (options_.poll_hz > 0 && options_.poll_hz < udm::kMaxRateHz) {
    StartPolling(options_.poll_hz, std::string(1, udm::kMeasure));
  } else {
    Write(std::string(1, udm::kMeasure));
  }
}

void RangerDriver::Range(DoneFn done) {
  boost::asio::post(io_, [this, done = std::move(done)]() mutable {
    auto timer = std::make_shared<boost::asio::steady_timer>(io_, options_.timeout);
    waiters_.push_back({std::move(done), timer});
    timer->async_wait([this, timer](const boost::system::error_code& ec) {
      if (ec) return;
      for (auto it = waiters_.begin(); it != waiters_.end(); ++it) {
        if (it->timer != timer) continue;
        DoneFn d = std::move(it->done);
        waiters_.erase(it);
        d(false, RangerState(), "the ranger did not answer (" + status().message() + ")");
        return;
      }
    });
    Write(std::string(1, udm::kMeasure));
  });
}

void RangerDriver::OnSerialBytes(const uint8_t* data, size_t size, int64_t now_ns) {
  for (size_t i = 0; i < size; ++i) {
    if (parser_.Feed(data[i]) != ParseResult::kGood) continue;
    const auto answer = udm::Decode(parser_.frame());
    if (!answer) continue;
    RangerState state;
    state.set_valid(answer->has_value());
    if (*answer) state.set_range_in(**answer);
    StampReading(state.mutable_stamp(), now_ns);
    // At the full rate the next request goes out with each answer: the ranger paces itself,
    // and a timer of the same period would keep colliding with its measurements.
    if (options_.poll_hz >= udm::kMaxRateHz) Write(std::string(1, udm::kMeasure));
    on_reading_(state);
    // One answer serves every request waiting for it: they asked during one measurement.
    auto waiters = std::move(waiters_);
    waiters_.clear();
    for (auto& w : waiters) {
      w.timer->cancel();
      w.done(true, state, "");
    }
  }
}

}  // namespace igms::devices
