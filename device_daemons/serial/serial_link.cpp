#include "device_daemons/serial/serial_link.h"

#include <boost/asio/post.hpp>
#include <boost/asio/write.hpp>

#include "common/base/clock.h"

namespace igms::devices {

namespace asio = boost::asio;

bool SerialLinkOptions::Check(std::string* error) const {
  if (port.empty()) {
    *error = "no serial port given";
    return false;
  }
  if (baud == 0 || silence_timeout.count() <= 0 || backoff_min.count() <= 0 ||
      backoff_max < backoff_min) {
    *error = "serial link options out of range (baud, silence timeout, backoff)";
    return false;
  }
  return true;
}

SerialLink::SerialLink(asio::io_context& io, SerialLinkOptions options, BytesFn on_bytes,
                       StateFn on_state)
    : io_(io),
      options_(std::move(options)),
      on_bytes_(std::move(on_bytes)),
      on_state_(std::move(on_state)),
      port_(io),
      reopen_timer_(io),
      watchdog_(io),
      backoff_(options_.backoff_min) {}

void SerialLink::Start() {
  asio::post(io_, [this] {
    TryOpen();
    ArmWatchdog();
  });
}

void SerialLink::Stop() {
  asio::post(io_, [this] {
    stopped_ = true;
    ++generation_;
    boost::system::error_code ignored;
    port_.close(ignored);
    reopen_timer_.cancel();
    watchdog_.cancel();
  });
}

void SerialLink::SetState(LinkState state, const std::string& message) {
  if (state == state_ && state != CONNECTING) return;
  state_ = state;
  if (on_state_) on_state_(state, message);
}

void SerialLink::TryOpen() {
  if (stopped_) return;
  boost::system::error_code ec;
  port_.open(options_.port, ec);
  if (!ec) port_.set_option(asio::serial_port::baud_rate(options_.baud), ec);
  if (!ec) port_.set_option(asio::serial_port::character_size(8), ec);
  if (!ec) port_.set_option(asio::serial_port::parity(asio::serial_port::parity::none), ec);
  if (!ec) port_.set_option(asio::serial_port::stop_bits(asio::serial_port::stop_bits::one), ec);
  if (!ec) {
    port_.set_option(asio::serial_port::flow_control(asio::serial_port::flow_control::none), ec);
  }
  if (ec) {
    boost::system::error_code ignored;
    port_.close(ignored);
    ScheduleReopen("cannot open " + options_.port + ": " + ec.message());
    return;
  }
  last_rx_ = std::chrono::steady_clock::now();
  writes_.clear();
  writing_ = false;
  SetState(CONNECTING, "opened " + options_.port);
  ReadMore();
}

void SerialLink::ScheduleReopen(const std::string& why) {
  if (stopped_) return;
  ++generation_;
  boost::system::error_code ignored;
  port_.close(ignored);
  SetState(REOPENING, why);
  ++reopens_;
  reopen_timer_.expires_after(backoff_);
  backoff_ = std::min(backoff_ * 2, options_.backoff_max);
  reopen_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec) TryOpen();
  });
}

void SerialLink::ReadMore() {
  const uint64_t generation = generation_;
  port_.async_read_some(asio::buffer(buffer_),
                        [this, generation](const boost::system::error_code& ec, size_t n) {
                          if (generation != generation_ || stopped_) return;
                          if (ec) {
                            ScheduleReopen(options_.port + " failed: " + ec.message());
                            return;
                          }
                          const int64_t now = MonotonicNs();
                          last_rx_ = std::chrono::steady_clock::now();
                          backoff_ = options_.backoff_min;
                          if (state_ != CONNECTED)
                            SetState(CONNECTED, "receiving from " + options_.port);
                          on_bytes_(buffer_, n, now);
                          ReadMore();
                        });
}

void SerialLink::Write(std::string bytes) {
  asio::post(io_, [this, bytes = std::move(bytes)]() mutable {
    if (stopped_ || !port_.is_open()) return;  // a closed port loses the request, as a line would
    writes_.push_back(std::move(bytes));
    if (!writing_) WriteMore();
  });
}

void SerialLink::WriteMore() {
  if (writes_.empty() || !port_.is_open()) {
    writing_ = false;
    return;
  }
  writing_ = true;
  const uint64_t generation = generation_;
  asio::async_write(port_, asio::buffer(writes_.front()),
                    [this, generation](const boost::system::error_code& ec, size_t) {
                      if (generation != generation_ || stopped_) return;
                      writes_.pop_front();
                      if (ec) {
                        ScheduleReopen(options_.port + " write failed: " + ec.message());
                        return;
                      }
                      WriteMore();
                    });
}

void SerialLink::ArmWatchdog() {
  watchdog_.expires_after(options_.silence_timeout / 4);
  watchdog_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || stopped_) return;
    const auto silent = std::chrono::steady_clock::now() - last_rx_;
    if (port_.is_open()) {
      if (silent > 2 * options_.silence_timeout) {
        ScheduleReopen(options_.port + " silent; reopening");
      } else if (silent > options_.silence_timeout && state_ == CONNECTED) {
        SetState(STALE,
                 options_.port + " silent for " +
                     std::to_string(
                         std::chrono::duration_cast<std::chrono::milliseconds>(silent).count()) +
                     " ms");
      }
    }
    ArmWatchdog();
  });
}

}  // namespace igms::devices
