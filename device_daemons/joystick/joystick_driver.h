// JoystickDriver: the serial side of igms-joystickd. Talks CerealBox to a FlyBox (or the
// simulator) through a SerialLink and turns each report into a time-stamped JoystickState.
//
// On every (re)open it identifies the box ('T', expecting the 44-character reply), sends
// the FlyBox configuration ('c', expecting "a\n"), then either polls with 'p' at
// options.poll_hz (each request goes out one cycle before its report is read, as the
// thesis's 2.1.2 describes) or, with options.continuous, starts the box's own stream ('C').
// An unanswered identification or configuration is retried every options.init_timeout.
//
// Threading: runs on the io_context's thread; on_reading and on_status are called there.
// status() is thread-safe.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <functional>
#include <mutex>
#include <optional>
#include <string>

#include "device_daemons/joystick/cerealbox_protocol.h"
#include "device_daemons/serial/serial_link.h"
#include "igms/devices.pb.h"

namespace igms::devices {

struct JoystickDriverOptions {
  SerialLinkOptions link;
  double poll_hz = 50.0;  // clamped to the FlyBox's 50 Hz
  bool continuous = false;
  std::chrono::milliseconds init_timeout{500};
  bool Check(std::string* error) const;
};

class JoystickDriver {
 public:
  using ReadingFn = std::function<void(const JoystickState&)>;
  using StatusFn = std::function<void(const LinkStatus&)>;

  JoystickDriver(boost::asio::io_context& io, JoystickDriverOptions options, ReadingFn on_reading,
                 StatusFn on_status = {});
  void Start();
  void Stop();
  LinkStatus status() const;

 private:
  enum class Phase { kIdent, kConfig, kRun };
  void OnState(LinkState state, const std::string& message);
  void OnBytes(const uint8_t* data, size_t size, int64_t now_ns);
  void BeginInit();
  void ArmInitTimer();
  void ArmPollTimer();
  void UpdateStatus(const std::function<void(LinkStatus&)>& change);

  boost::asio::io_context& io_;
  JoystickDriverOptions options_;
  ReadingFn on_reading_;
  StatusFn on_status_;
  SerialLink link_;
  boost::asio::steady_timer init_timer_;
  boost::asio::steady_timer poll_timer_;
  Phase phase_ = Phase::kIdent;
  std::string reply_;  // identification / acknowledgement being collected
  cerealbox::ReportParser parser_{cerealbox::kFlyBoxLayout};
  uint64_t sequence_ = 0;
  mutable std::mutex status_mutex_;
  LinkStatus status_;
};

// Converts a decoded FlyBox report (kFlyBoxLayout) to the published state (stamp unset).
JoystickState ToJoystickState(const cerealbox::Report& report);

}  // namespace igms::devices
