// igms-joystickd's body: the FlyBox driver (or its simulator, or a replay) behind
// igms.devices.JoystickService (Live, Status) and igms.devices.SimService.Inject, which
// takes a JoystickState as the operator's hand on the simulated box. See daemon_base.h.
// With `gamepad` the device is a Linux joystick at the source's port path, read by a
// GamepadReader (gamepad_reader.h) instead of the FlyBox driver; it publishes the same
// JoystickState.
#pragma once

#include "common/config/process_options.h"
#include "device_daemons/joystick/flybox_sim.h"
#include "device_daemons/joystick/gamepad_reader.h"
#include "device_daemons/joystick/joystick_driver.h"
#include "device_daemons/serial/daemon_base.h"

namespace igms::devices {

struct JoystickDaemonOptions {
  bool continuous = false;     // the FlyBox streams ('C') instead of being polled
  bool gamepad = false;        // the port is a Linux joystick device, not a FlyBox
  std::string gamepad_device;  // the gamepad key or flag: that device stands for the serial port
  // The keys under gamepad_map as read, each optional (an empty list: GamepadMapping's):
  // axes: [x, y, twist, lever0, lever1] (device axis numbers, -1 unmapped), invert:
  // [5 booleans], buttons: [the device buttons of FlyBox buttons 1-8], trigger: N.
  struct MapKeys {
    static constexpr GamepadMapping kDefaults{};
    std::vector<int> axes = std::vector<int>(kDefaults.axes.begin(), kDefaults.axes.end());
    std::vector<bool> invert = std::vector<bool>(kDefaults.invert.begin(), kDefaults.invert.end());
    std::vector<int> buttons = std::vector<int>(kDefaults.buttons.begin(), kDefaults.buttons.end());
    int trigger = kDefaults.trigger;
  } gamepad_map;
  GamepadMapping mapping;  // from gamepad_map, by ReadGamepadMapping
};

// The joystick's keys (processes.NAME): the daemon's shared ones (DaemonKeys, bound to
// `daemon`), continuous, gamepad and gamepad_map (bound to `options`).
config::Keys JoystickKeys(JoystickDaemonOptions* options, DaemonConfig* daemon);

// Sets options->mapping from options->gamepad_map. False with a message naming the key of
// `process` at fault when it is invalid.
bool ReadGamepadMapping(const config::ProcessOptions& process, JoystickDaemonOptions* options,
                        std::string* error);

class JoystickDaemon : public DaemonBase<JoystickState> {
 public:
  JoystickDaemon(boost::asio::io_context& io, DaemonOptions options, net::ServerOptions server,
                 JoystickDaemonOptions joystick = {});

 private:
  std::unique_ptr<SimulatedDevice> MakeSimulator(std::string* error) override;
  bool StartDevice(const SerialLinkOptions& link, std::string* error) override;
  void StopDevice() override;
  LinkStatus DeviceStatus() const override;
  bool InjectInput(const SimInjectRequest& request, SimulatedDevice& sim,
                   SimInjectResponse* response, std::string* error) override;

  JoystickDaemonOptions joystick_;
  std::unique_ptr<JoystickDriver> driver_;
  std::unique_ptr<GamepadReader> gamepad_;
};

}  // namespace igms::devices
