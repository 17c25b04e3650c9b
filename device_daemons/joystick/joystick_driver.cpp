#include "device_daemons/joystick/joystick_driver.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/asio/post.hpp>

#include "common/base/clock.h"

namespace igms::devices {

bool JoystickDriverOptions::Check(std::string* error) const {
  if (!link.Check(error)) return false;
  if (!(poll_hz > 0)) {
    *error = "joystick poll rate must be positive";
    return false;
  }
  return true;
}

JoystickState ToJoystickState(const cerealbox::Report& r) {
  JoystickState s;
  s.set_x(r.analog[0]);
  s.set_y(r.analog[1]);
  s.set_twist(r.analog[2]);
  s.set_lever0(r.analog[3]);
  s.set_lever1(r.analog[4]);
  s.set_buttons(r.digital & 0xFF);
  s.set_trigger((r.digital >> cerealbox::kTriggerBit) & 1U);
  return s;
}

JoystickDriver::JoystickDriver(boost::asio::io_context& io, JoystickDriverOptions options,
                               ReadingFn on_reading, StatusFn on_status)
    : io_(io),
      options_(std::move(options)),
      on_reading_(std::move(on_reading)),
      on_status_(std::move(on_status)),
      link_(
          io, options_.link, [this](const uint8_t* d, size_t n, int64_t t) { OnBytes(d, n, t); },
          [this](LinkState s, const std::string& m) { OnState(s, m); }),
      init_timer_(io),
      poll_timer_(io) {
  options_.poll_hz = std::min(options_.poll_hz, 50.0);
  status_.set_port(options_.link.port);
}

void JoystickDriver::Start() { link_.Start(); }

void JoystickDriver::Stop() {
  link_.Stop();
  boost::asio::post(io_, [this] {
    init_timer_.cancel();
    poll_timer_.cancel();
  });
}

LinkStatus JoystickDriver::status() const {
  std::lock_guard lock(status_mutex_);
  return status_;
}

void JoystickDriver::UpdateStatus(const std::function<void(LinkStatus&)>& change) {
  LinkStatus copy;
  {
    std::lock_guard lock(status_mutex_);
    change(status_);
    status_.set_bad_frames(parser_.bad_frames());
    status_.set_garbage_bytes(parser_.garbage_bytes());
    status_.set_reopens(link_.reopens());
    copy = status_;
  }
  if (on_status_) on_status_(copy);
}

void JoystickDriver::OnState(LinkState state, const std::string& message) {
  spdlog::info("joystick: {} ({})", LinkState_Name(state), message);
  UpdateStatus([&](LinkStatus& s) {
    // Connected only once the box has answered; the link's CONNECTED means bytes arrive.
    if (state != CONNECTED || phase_ == Phase::kRun) s.set_state(state);
    s.set_message(message);
  });
  if (state == CONNECTING) BeginInit();
  if (state == REOPENING) {
    init_timer_.cancel();
    poll_timer_.cancel();
  }
}

void JoystickDriver::BeginInit() {
  phase_ = Phase::kIdent;
  reply_.clear();
  poll_timer_.cancel();
  link_.Write("T");
  ArmInitTimer();
}

void JoystickDriver::ArmInitTimer() {
  init_timer_.expires_after(options_.init_timeout);
  init_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || phase_ == Phase::kRun) return;
    spdlog::warn("joystick: no answer to {}, retrying", phase_ == Phase::kIdent ? "'T'" : "'c'");
    BeginInit();
  });
}

// Deadlines advance by whole periods, so timer lateness does not lower the rate.
void JoystickDriver::ArmPollTimer() {
  const auto period = std::chrono::nanoseconds(static_cast<int64_t>(1e9 / options_.poll_hz));
  const auto now = std::chrono::steady_clock::now();
  auto next = poll_timer_.expiry() + period;
  if (next < now || next > now + period) next = now + period;
  poll_timer_.expires_at(next);
  poll_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || phase_ != Phase::kRun) return;
    link_.Write("p");
    ArmPollTimer();
  });
}

void JoystickDriver::OnBytes(const uint8_t* data, size_t size, int64_t now_ns) {
  for (size_t i = 0; i < size; ++i) {
    const uint8_t byte = data[i];
    if (phase_ == Phase::kIdent) {
      reply_.push_back(static_cast<char>(byte));
      const size_t at = reply_.find(cerealbox::kCopyright);
      if (at == std::string::npos) {
        if (reply_.size() > 2 * cerealbox::kIdentLength) reply_.erase(0, cerealbox::kIdentLength);
        continue;
      }
      if (reply_.size() - at < cerealbox::kIdentLength) continue;
      char type = 0;
      std::string version;
      if (!cerealbox::ParseIdent(std::string_view(reply_).substr(at, cerealbox::kIdentLength),
                                 &type, &version)) {
        reply_.erase(0, at + 1);
        continue;
      }
      spdlog::info("joystick: CerealBox type {} EEPROM {} on {}", type, version, link_.port());
      phase_ = Phase::kConfig;
      reply_.clear();
      link_.Write(cerealbox::ConfigCommand(cerealbox::kFlyBoxLayout));
      ArmInitTimer();
    } else if (phase_ == Phase::kConfig) {
      reply_.push_back(static_cast<char>(byte));
      if (reply_.find("a\n") == std::string::npos) continue;
      phase_ = Phase::kRun;
      init_timer_.cancel();
      UpdateStatus([](LinkStatus& s) { s.set_state(CONNECTED); });
      if (options_.continuous) {
        link_.Write("C");
      } else {
        link_.Write("p");
        ArmPollTimer();
      }
    } else if (parser_.Feed(byte) == ParseResult::kGood) {
      JoystickState state = ToJoystickState(parser_.report());
      Stamp* stamp = state.mutable_stamp();
      stamp->set_sequence(++sequence_);
      stamp->set_receive_monotonic_ns(now_ns);
      stamp->set_receive_unix_ns(UnixNs());
      {
        std::lock_guard lock(status_mutex_);
        status_.set_readings(sequence_);
        status_.set_bad_frames(parser_.bad_frames());
        status_.set_garbage_bytes(parser_.garbage_bytes());
      }
      on_reading_(state);
    }
  }
}

}  // namespace igms::devices
