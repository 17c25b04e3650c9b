#include "device_daemons/serial/device_driver.h"

#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>

#include "common/base/clock.h"

namespace igms::devices {

DeviceDriver::DeviceDriver(boost::asio::io_context& io, SerialLinkOptions link, std::string name,
                           StatusFn on_status)
    : io_(io),
      name_(std::move(name)),
      on_status_(std::move(on_status)),
      link_(
          io, std::move(link),
          [this](const uint8_t* d, size_t n, int64_t t) { OnSerialBytes(d, n, t); },
          [this](LinkState s, const std::string& m) { OnState(s, m); }),
      poll_timer_(io) {
  status_.set_port(link_.port());
  status_.set_state(CONNECTING);
}

void DeviceDriver::Start() { link_.Start(); }

void DeviceDriver::Stop() {
  link_.Stop();
  boost::asio::post(io_, [this] { poll_timer_.cancel(); });
}

LinkStatus DeviceDriver::status() const {
  std::lock_guard lock(mutex_);
  LinkStatus copy = status_;
  copy.set_bad_frames(bad_frames());
  copy.set_garbage_bytes(garbage_bytes());
  copy.set_reopens(link_.reopens());
  return copy;
}

void DeviceDriver::Publish(const std::function<void(LinkStatus&)>& change) {
  {
    std::lock_guard lock(mutex_);
    change(status_);
  }
  if (on_status_) on_status_(status());
}

void DeviceDriver::OnState(LinkState state, const std::string& message) {
  spdlog::info("{}: {} ({})", name_, LinkState_Name(state), message);
  if (state == CONNECTING || state == REOPENING) {
    answered_ = false;
    StopPolling();
  }
  Publish([&](LinkStatus& s) {
    // The link's CONNECTED means bytes arrive; the device counts as connected once it has
    // answered in its own protocol.
    if (state != CONNECTED || answered_) s.set_state(state);
    s.set_message(message);
  });
  if (state == CONNECTING) OnOpened();
}

void DeviceDriver::MarkConnected() {
  if (answered_) return;
  answered_ = true;
  Publish([](LinkStatus& s) { s.set_state(CONNECTED); });
}

void DeviceDriver::StartPolling(double hz, std::string request) {
  poll_period_ = std::chrono::nanoseconds(static_cast<int64_t>(1e9 / hz));
  poll_request_ = std::move(request);
  link_.Write(poll_request_);
  poll_timer_.expires_after(poll_period_);
  ArmPoll();
}

void DeviceDriver::StopPolling() {
  poll_request_.clear();
  poll_timer_.cancel();
}

// Deadlines advance by whole periods, so timer lateness does not lower the rate.
void DeviceDriver::ArmPoll() {
  poll_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || poll_request_.empty()) return;
    link_.Write(poll_request_);
    const auto now = std::chrono::steady_clock::now();
    auto next = poll_timer_.expiry() + poll_period_;
    if (next < now) next = now;  // fell a whole period behind: do not burst
    poll_timer_.expires_at(next);
    ArmPoll();
  });
}

void DeviceDriver::StampReading(Stamp* stamp, int64_t now_ns, uint64_t device_time_us) {
  stamp->set_sequence(++sequence_);
  stamp->set_device_time_us(device_time_us);
  stamp->set_receive_monotonic_ns(now_ns);
  stamp->set_receive_unix_ns(UnixNs());
  if (!answered_) MarkConnected();
  std::lock_guard lock(mutex_);
  status_.set_readings(sequence_);
}

}  // namespace igms::devices
