// DragonDriver: the serial side of igms-voiced against a Dragon speech PC (or its
// simulator), dragon_protocol.h. On every (re)open it tells the device the system's state
// and probes it kProbeHz times a second, so the watchdog hears from a device that is
// otherwise silent until the operator speaks; the "00" answers mark it connected.
//
// Every command code is checked against the system's state, which the control client sets
// with SetState: a command valid in it is published as a VoiceState (code, phrase,
// confidence 1, the state) and moves the state on as PredictNextState says until the
// control client says otherwise; any other is rejected and counted (rejected()), because a
// Dragon that ignores "S d" still has its own state, which may have fallen behind
// (Cooke, section 2.1.6). Threading as DeviceDriver; SetState and the counters are
// thread-safe.
//
// The device answers each probe and state change with one "00", in order, so the driver
// knows when the device has taken a state: SetState's `done` runs (on the io thread) once
// that answer is in, or after kAckTimeout when it never comes (a Dragon that does not
// know "S d", a line that lost the answer), or at a reopen.
#pragma once

#include <atomic>
#include <boost/asio/steady_timer.hpp>
#include <deque>
#include <functional>
#include <memory>

#include "device_daemons/serial/device_driver.h"
#include "device_daemons/voice/dragon_protocol.h"

namespace igms::voice {

class DragonDriver : public devices::DeviceDriver {
 public:
  using ReadingFn = std::function<void(const devices::VoiceState&)>;

  DragonDriver(boost::asio::io_context& io, devices::SerialLinkOptions link,
               OperatorState initial_state, ReadingFn on_reading, StatusFn on_status = {});
  static constexpr std::chrono::milliseconds kAckTimeout{300};
  void SetState(OperatorState state, std::function<void()> done = {});
  void Stop();  // hides DeviceDriver::Stop: the probes stop too
  OperatorState state() const { return static_cast<OperatorState>(state_.load()); }
  uint64_t rejected() const { return rejected_; }

 private:
  void OnOpened() override;
  void OnSerialBytes(const uint8_t* data, size_t size, int64_t now_ns) override;
  uint64_t bad_frames() const override { return parser_.bad_frames(); }
  uint64_t garbage_bytes() const override { return parser_.garbage_bytes(); }

  void Request(std::string bytes);  // a request the device answers with "00"
  void ArmProbe();
  void FinishWaiters(bool all);
  void OnReport(int64_t now_ns);

  ReadingFn on_reading_;
  boost::asio::steady_timer probe_timer_;
  boost::asio::steady_timer idle_timer_;  // bare digit pairs: see ReportParser::Idle
  uint64_t requests_ = 0;                 // requests written since the port opened
  uint64_t answers_ = 0;                  // "00" lines received since then
  struct Waiter {
    uint64_t request;
    std::function<void()> done;
    std::shared_ptr<boost::asio::steady_timer> timer;
  };
  std::deque<Waiter> waiters_;
  dragon::ReportParser parser_;
  std::atomic<int> state_;
  std::atomic<uint64_t> rejected_{0};
};

}  // namespace igms::voice
