#include "device_daemons/voice/dragon_driver.h"

#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>

#include "device_daemons/voice/voice_proto.h"

namespace igms::voice {

DragonDriver::DragonDriver(boost::asio::io_context& io, devices::SerialLinkOptions link,
                           OperatorState initial_state, ReadingFn on_reading, StatusFn on_status)
    : DeviceDriver(io, std::move(link), "voice", std::move(on_status)),
      on_reading_(std::move(on_reading)),
      probe_timer_(io),
      state_(static_cast<int>(initial_state)) {}

void DragonDriver::SetState(OperatorState state, std::function<void()> done) {
  state_ = static_cast<int>(state);
  boost::asio::post(io_, [this, state, done = std::move(done)]() mutable {
    Request(dragon::EncodeSetState(state));
    if (!done) return;
    auto timer = std::make_shared<boost::asio::steady_timer>(io_, kAckTimeout);
    waiters_.push_back({requests_, std::move(done), timer});
    timer->async_wait([this, timer](const boost::system::error_code& ec) {
      if (ec) return;
      for (auto it = waiters_.begin(); it != waiters_.end(); ++it) {
        if (it->timer != timer) continue;
        auto d = std::move(it->done);
        waiters_.erase(it);
        d();
        return;
      }
    });
  });
}

void DragonDriver::Stop() {
  boost::asio::post(io_, [this] { probe_timer_.cancel(); });
  DeviceDriver::Stop();
}

void DragonDriver::Request(std::string bytes) {
  ++requests_;
  Write(std::move(bytes));
}

// Probes go out on fixed deadlines; the counting needs them here, not in DeviceDriver's
// poller.
void DragonDriver::ArmProbe() {
  probe_timer_.expires_after(
      std::chrono::nanoseconds(static_cast<int64_t>(1e9 / dragon::kProbeHz)));
  probe_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec) return;
    Request(dragon::EncodeProbe());
    ArmProbe();
  });
}

void DragonDriver::FinishWaiters(bool all) {
  while (!waiters_.empty() && (all || waiters_.front().request <= answers_)) {
    Waiter w = std::move(waiters_.front());
    waiters_.pop_front();
    w.timer->cancel();
    w.done();
  }
}

void DragonDriver::OnOpened() {
  parser_.Reset();
  FinishWaiters(true);
  requests_ = answers_ = 0;
  Request(dragon::EncodeSetState(state()));
  Request(dragon::EncodeProbe());
  ArmProbe();
}

void DragonDriver::OnSerialBytes(const uint8_t* data, size_t size, int64_t now_ns) {
  for (size_t i = 0; i < size; ++i) {
    if (parser_.Feed(data[i]) != devices::ParseResult::kGood) continue;
    const auto command = parser_.report().command;
    if (!command) {
      MarkConnected();
      if (answers_ < requests_) ++answers_;
      FinishWaiters(false);
      continue;
    }
    const OperatorState now_state = state();
    if (!IsValid(now_state, *command)) {
      ++rejected_;
      spdlog::warn("voice: \"{}\" ({}) is not valid in state {}; rejected", Phrase(*command),
                   Code(*command), StateName(now_state));
      continue;
    }
    state_ = static_cast<int>(PredictNextState(now_state, *command));
    devices::VoiceState reading;
    StampReading(reading.mutable_stamp(), now_ns);
    reading.set_command(ToProto(*command));
    reading.set_confidence(1.0);
    reading.set_text(std::string(Phrase(*command)));
    reading.set_state(ToProto(now_state));
    on_reading_(reading);
  }
}

}  // namespace igms::voice
