// A simulated FlyBox: answers the CerealBox protocol (cerealbox_protocol.h) as the real box
// does, from a joystick state that tests and the sim service set. Runs inside a PtyHost.
#pragma once

#include <string>
#include <vector>

#include "device_daemons/joystick/cerealbox_protocol.h"
#include "device_daemons/serial/pty_host.h"
#include "igms/devices.pb.h"

namespace igms::devices {

class FlyBoxSim : public SimulatedDevice {
 public:
  static constexpr double kMaxRateHz = 50.0;  // thesis 2.1.4

  std::vector<std::string> OnInput(std::string_view bytes, int64_t now_ns) override;
  std::vector<std::string> Poll(int64_t now_ns, int64_t* next_wake_ns) override;

  // Axes clamped to [-1, 1]; buttons bit i = button i+1.
  void Set(const JoystickState& state);
  const cerealbox::Layout& layout() const { return layout_; }
  uint64_t reports_sent() const { return reports_; }

 private:
  std::string Report();

  cerealbox::Layout layout_ = cerealbox::kFlyBoxLayout;
  cerealbox::Report state_;
  std::string pending_config_;  // after 'c'/'s', until '\n'
  bool in_config_ = false;
  char config_command_ = 'c';
  bool continuous_ = false;
  int64_t next_report_ns_ = 0;
  uint64_t reports_ = 0;
};

}  // namespace igms::devices
