#include "device_daemons/platform/platform_driver.h"

#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>

namespace igms::devices {

bool PlatformDriverOptions::Check(std::string* error) const {
  if (!link.Check(error)) return false;
  if (!(poll_hz > 0) || poll_hz > 80) {
    *error = "platform poll rate must be in (0, 80] Hz";
    return false;
  }
  return true;
}

PlatformState ToPlatformState(const molly::Message& m) {
  PlatformState s;
  s.set_yaw_ticks(m.ticks.yaw);
  s.set_pitch_ticks(m.ticks.pitch);
  s.set_roll_ticks(m.ticks.roll);
  s.set_yaw_deg(molly::YawDeg(m.ticks.yaw));
  s.set_pitch_deg(molly::PitchRollDeg(m.ticks.pitch));
  s.set_roll_deg(molly::PitchRollDeg(m.ticks.roll));
  s.set_moving(m.moving);
  return s;
}

PlatformDriver::PlatformDriver(boost::asio::io_context& io, PlatformDriverOptions options,
                               ReadingFn on_reading, StatusFn on_status)
    : DeviceDriver(io, options.link, "platform", std::move(on_status)),
      options_(std::move(options)),
      on_reading_(std::move(on_reading)) {}

void PlatformDriver::OnOpened() {
  parser_.Reset();
  FailAll("the platform's port was reopened");
  steps_per_move_ = 0;
  StartPolling(options_.poll_hz, molly::EncodeQuery());
}

void PlatformDriver::FailAll(const std::string& why) {
  auto pending = std::move(pending_);
  pending_.clear();
  for (auto& p : pending) {
    p.timer->cancel();
    if (p.done) p.done(false, why);
  }
}

void PlatformDriver::Send(uint8_t head, std::string frame, DoneFn done) {
  auto timer = std::make_shared<boost::asio::steady_timer>(io_, options_.ack_timeout);
  pending_.push_back({head, std::move(done), timer});
  timer->async_wait([this, timer](const boost::system::error_code& ec) {
    if (ec) return;
    // The oldest command went unanswered: a lost frame. Fail it, keep the others.
    for (auto it = pending_.begin(); it != pending_.end(); ++it) {
      if (it->timer != timer) continue;
      DoneFn done = std::move(it->done);
      pending_.erase(it);
      if (done) done(false, "the platform did not acknowledge the command");
      return;
    }
  });
  Write(std::move(frame));
}

void PlatformDriver::SetOrientation(const molly::Ticks& ticks, uint32_t steps, DoneFn done) {
  boost::asio::post(io_, [this, ticks, steps, done = std::move(done)]() mutable {
    if (status().state() != CONNECTED && status().state() != STALE) {
      done(false, "the platform is not connected (" + status().message() + ")");
      return;
    }
    if (steps != 0 && steps != steps_per_move_) {
      steps_per_move_ = steps;
      Send(molly::kSpeed, molly::EncodeSpeed(steps), nullptr);
    }
    Send(molly::kSet, molly::EncodeSet(ticks), std::move(done));
  });
}

void PlatformDriver::ResetZero(DoneFn done) {
  boost::asio::post(io_, [this, done = std::move(done)]() mutable {
    if (status().state() != CONNECTED && status().state() != STALE) {
      done(false, "the platform is not connected (" + status().message() + ")");
      return;
    }
    Send(molly::kZero, molly::EncodeZero(), std::move(done));
  });
}

void PlatformDriver::OnSerialBytes(const uint8_t* data, size_t size, int64_t now_ns) {
  for (size_t i = 0; i < size; ++i) {
    if (parser_.Feed(data[i]) != ParseResult::kGood) continue;
    const auto m = molly::Decode(parser_.frame());
    if (!m) continue;
    if (m->head == molly::kOrientation) {
      PlatformState state = ToPlatformState(*m);
      StampReading(state.mutable_stamp(), now_ns);
      on_reading_(state);
    } else if (m->head == molly::kAck) {
      // Acknowledgements come in command order; earlier unacknowledged ones were lost.
      while (!pending_.empty()) {
        Pending p = std::move(pending_.front());
        pending_.pop_front();
        p.timer->cancel();
        if (p.head == m->acked) {
          if (p.done) p.done(true, "");
          break;
        }
        if (p.done) p.done(false, "the platform did not acknowledge the command");
      }
    }
  }
}

}  // namespace igms::devices
