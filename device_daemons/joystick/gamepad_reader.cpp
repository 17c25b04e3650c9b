#include "device_daemons/joystick/gamepad_reader.h"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <boost/asio/post.hpp>
#include <cerrno>

#include "common/base/clock.h"
#include "common/base/errno_text.h"

namespace igms::devices {

bool GamepadReaderOptions::Check(std::string* error) const {
  if (path.empty()) {
    *error = "--gamepad needs a device path such as /dev/input/js0";
    return false;
  }
  if (!(rate_hz > 0) || rate_hz > 1000) {
    *error = "gamepad rate must be in (0, 1000] Hz";
    return false;
  }
  if (min_spacing.count() < 0 ||
      min_spacing > std::chrono::nanoseconds(static_cast<int64_t>(1e9 / rate_hz))) {
    *error = "gamepad min_spacing must be in [0, 1 / rate_hz]";
    return false;
  }
  if (backoff_min.count() <= 0 || backoff_max < backoff_min) {
    *error = "gamepad backoff must satisfy 0 < min <= max";
    return false;
  }
  return mapping.Check(error);
}

GamepadReader::GamepadReader(boost::asio::io_context& io, GamepadReaderOptions options,
                             ReadingFn on_reading)
    : io_(io),
      options_(std::move(options)),
      on_reading_(std::move(on_reading)),
      decoder_(options_.mapping),
      device_(io),
      reopen_timer_(io),
      tick_timer_(io),
      backoff_(options_.backoff_min),
      period_(static_cast<int64_t>(1e9 / options_.rate_hz)) {
  status_.set_port(options_.path);
}

void GamepadReader::Start() {
  boost::asio::post(io_, [this] { TryOpen(); });
}

void GamepadReader::Stop() {
  boost::asio::post(io_, [this] {
    stopped_ = true;
    reopen_timer_.cancel();
    tick_timer_.cancel();
    boost::system::error_code ignored;
    device_.close(ignored);
  });
}

LinkStatus GamepadReader::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

void GamepadReader::SetState(LinkState state, const std::string& message) {
  {
    std::lock_guard lock(mutex_);
    if (status_.state() == state && status_.message() == message) return;
    status_.set_state(state);
    status_.set_message(message);
  }
  const auto level = state == REOPENING ? spdlog::level::warn : spdlog::level::info;
  spdlog::log(level, "joystick: {} ({})", LinkState_Name(state), message);
}

void GamepadReader::TryOpen() {
  if (stopped_) return;
  // Non-blocking: a FIFO opens without a writer, and reads go through the reactor.
  const int fd = ::open(options_.path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    Vanished("cannot open " + options_.path + ": " + ErrnoText(errno));
    return;
  }
  boost::system::error_code ec;
  device_.assign(fd, ec);
  if (!ec) device_.non_blocking(true, ec);
  if (ec) {
    if (device_.is_open()) {
      boost::system::error_code ignored;
      device_.close(ignored);
    } else {
      ::close(fd);
    }
    Vanished("cannot use " + options_.path + ": " + ec.message());
    return;
  }
  if (opens_++ > 0) {
    std::lock_guard lock(mutex_);
    status_.set_reopens(status_.reopens() + 1);
  }
  decoder_.Reset();
  reported_ = false;
  SetState(CONNECTING, "opened " + options_.path);
  ReadMore();
}

void GamepadReader::ReadMore() {
  // Wait for readability, then read without blocking: a FIFO reopened after its writer left
  // reads end-of-file at once, but is not readable until a writer comes back.
  device_.async_wait(
      boost::asio::posix::descriptor_base::wait_read, [this](const boost::system::error_code& ec) {
        if (stopped_ || ec == boost::asio::error::operation_aborted) return;
        boost::system::error_code read_ec = ec;
        size_t n = 0;
        if (!read_ec) n = device_.read_some(boost::asio::buffer(buffer_), read_ec);
        if (read_ec == boost::asio::error::would_block ||
            read_ec == boost::asio::error::try_again) {
          ReadMore();
          return;
        }
        if (read_ec) {
          Vanished(read_ec == boost::asio::error::eof
                       ? options_.path + " closed (unplugged, or its writer went away)"
                       : "reading " + options_.path + ": " + read_ec.message());
          return;
        }
        const int64_t now = MonotonicNs();
        if (decoder_.Feed(buffer_, n) > 0) {
          backoff_ = options_.backoff_min;
          if (!reported_) {
            reported_ = true;
            SetState(CONNECTED, "receiving from " + options_.path);
          }
          // A change goes out at once, or as soon as the spacing allows.
          const int64_t due =
              last_publish_ns_ + std::chrono::nanoseconds(options_.min_spacing).count();
          if (now >= due) {
            PublishNow(now);
          } else {
            ArmTick(std::chrono::nanoseconds(due - now));
          }
        }
        ReadMore();
      });
}

void GamepadReader::Vanished(const std::string& why) {
  boost::system::error_code ignored;
  device_.close(ignored);
  tick_timer_.cancel();
  reported_ = false;
  SetState(REOPENING, why);
  reopen_timer_.expires_after(backoff_);
  backoff_ = std::min(backoff_ * 2, options_.backoff_max);
  reopen_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec) TryOpen();
  });
}

void GamepadReader::PublishNow(int64_t now_ns) {
  JoystickState s = decoder_.state();
  Stamp* stamp = s.mutable_stamp();
  stamp->set_sequence(++sequence_);
  stamp->set_device_time_us(static_cast<uint64_t>(decoder_.last_event_ms()) * 1000);
  stamp->set_receive_monotonic_ns(now_ns);
  stamp->set_receive_unix_ns(UnixNs());
  {
    std::lock_guard lock(mutex_);
    status_.set_readings(sequence_);
  }
  last_publish_ns_ = now_ns;
  on_reading_(s);
  ArmTick(period_);
}

void GamepadReader::ArmTick(std::chrono::nanoseconds delay) {
  tick_timer_.expires_after(delay);
  tick_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || stopped_ || !reported_) return;
    PublishNow(MonotonicNs());
  });
}

}  // namespace igms::devices
