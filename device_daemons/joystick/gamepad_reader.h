// GamepadReader: igms-joystickd's source when the joystick is a Linux joystick device
// (`--gamepad /dev/input/js0`): it opens the device read-only, decodes its js_event records
// (gamepad.h) and publishes the FlyBox's JoystickState at the FlyBox's 50 Hz.
//
// Publishing: while the device is open and has reported (its INIT events come at once on a
// real device), a reading goes out every 1/rate_hz seconds (the FlyBox's 50 Hz) while the
// stick is still, and at once when events arrive, so a change reaches subscribers without
// waiting for the next period; min_spacing bounds the rate while the stick moves (200 a
// second by default). A subscriber asking a rate gets that rate (reading_hub.h).
// device_time_us is the driver's time of the latest event (milliseconds, times 1000).
//
// Faults, as a serial port's (serial_link.h): a device that cannot be opened, fails a read
// or reaches end of file (unplugged; a FIFO whose writer closed) is reported REOPENING with
// the reason and reopened with exponential backoff between backoff_min and backoff_max;
// each successful open reports CONNECTING, the first event after it CONNECTED. A gamepad
// left alone is silent, so silence is no fault. Record lengths are fixed, so there is no
// garbage to resynchronise on; a short read waits for the rest of its record.
//
// Threading: runs on the io_context's thread; on_reading is called there. status() is
// thread-safe; Stop() must be called before destruction, then the io thread stopped.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <functional>
#include <mutex>
#include <string>

#include "device_daemons/joystick/gamepad.h"
#include "igms/devices.pb.h"

namespace igms::devices {

struct GamepadReaderOptions {
  std::string path;
  GamepadMapping mapping;
  double rate_hz = 50.0;
  std::chrono::milliseconds min_spacing{5};
  std::chrono::milliseconds backoff_min{20};
  std::chrono::milliseconds backoff_max{2000};
  bool Check(std::string* error) const;
};

class GamepadReader {
 public:
  using ReadingFn = std::function<void(const JoystickState&)>;

  GamepadReader(boost::asio::io_context& io, GamepadReaderOptions options, ReadingFn on_reading);
  void Start();
  void Stop();
  LinkStatus status() const;

 private:
  void TryOpen();
  void ReadMore();
  void Vanished(const std::string& why);
  void ArmTick(std::chrono::nanoseconds delay);
  void PublishNow(int64_t now_ns);
  void SetState(LinkState state, const std::string& message);

  boost::asio::io_context& io_;
  GamepadReaderOptions options_;
  ReadingFn on_reading_;
  GamepadDecoder decoder_;
  boost::asio::posix::stream_descriptor device_;
  boost::asio::steady_timer reopen_timer_;
  boost::asio::steady_timer tick_timer_;
  uint8_t buffer_[256];
  std::chrono::milliseconds backoff_;
  std::chrono::nanoseconds period_;
  bool stopped_ = false;
  bool reported_ = false;  // an event since the last open
  uint64_t opens_ = 0;
  uint64_t sequence_ = 0;
  int64_t last_publish_ns_ = 0;
  mutable std::mutex mutex_;
  LinkStatus status_;
};

}  // namespace igms::devices
