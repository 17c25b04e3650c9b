// SerialLink: one device's serial port through Boost.Asio's serial_port, with a watchdog.
//
// The link opens the port (8N1 at options.baud), hands every received chunk to on_bytes
// with the CLOCK_MONOTONIC time it arrived, and writes what Write() is given, in order, one
// write in flight. The watchdog notices a device that has gone silent longer than
// options.silence_timeout (state STALE) and, after a second silence period, or at once when
// the port fails or vanishes, closes and reopens it with exponential backoff between
// options.backoff_min and options.backoff_max (state REOPENING). Each successful open
// reports CONNECTING, so the daemon can (re)initialise the device; the first bytes after
// it report CONNECTED.
//
// Threading: everything runs on the io_context's thread; Write() and Stop() may be called
// from any thread (they post). Callbacks run on the io thread.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/serial_port.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <string>

#include "igms/devices.pb.h"

namespace igms::devices {

struct SerialLinkOptions {
  std::string port;
  unsigned baud = 9600;
  std::chrono::milliseconds silence_timeout{500};
  std::chrono::milliseconds backoff_min{20};
  std::chrono::milliseconds backoff_max{2000};
  bool Check(std::string* error) const;
};

class SerialLink {
 public:
  using BytesFn = std::function<void(const uint8_t* data, size_t size, int64_t monotonic_ns)>;
  using StateFn = std::function<void(LinkState state, const std::string& message)>;

  SerialLink(boost::asio::io_context& io, SerialLinkOptions options, BytesFn on_bytes,
             StateFn on_state);
  void Start();
  void Stop();
  void Write(std::string bytes);

  LinkState state() const { return state_; }
  uint64_t reopens() const { return reopens_; }
  const std::string& port() const { return options_.port; }

 private:
  void TryOpen();
  void ScheduleReopen(const std::string& why);
  void ReadMore();
  void WriteMore();
  void ArmWatchdog();
  void SetState(LinkState state, const std::string& message);

  boost::asio::io_context& io_;
  SerialLinkOptions options_;
  BytesFn on_bytes_;
  StateFn on_state_;
  boost::asio::serial_port port_;
  boost::asio::steady_timer reopen_timer_;
  boost::asio::steady_timer watchdog_;
  std::chrono::milliseconds backoff_;
  std::chrono::steady_clock::time_point last_rx_;
  LinkState state_ = CONNECTING;
  uint64_t reopens_ = 0;
  uint64_t generation_ = 0;  // bumped on every close, so stale callbacks are ignored
  bool stopped_ = false;
  std::deque<std::string> writes_;
  bool writing_ = false;
  uint8_t buffer_[256];
};

}  // namespace igms::devices
