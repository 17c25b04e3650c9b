// igms-joystickd's body: the FlyBox driver (or its simulator, or a replay) behind
// igms.devices.JoystickService (Live, Status) and igms.devices.SimService.Inject, which
// takes a JoystickState as the operator's hand on the simulated box. See daemon_base.h.
#pragma once

#include "device_daemons/joystick/flybox_sim.h"
#include "device_daemons/joystick/joystick_driver.h"
#include "device_daemons/serial/daemon_base.h"

namespace igms::devices {

class JoystickDaemon : public DaemonBase<JoystickState> {
 public:
  JoystickDaemon(boost::asio::io_context& io, DaemonOptions options, net::ServerOptions server,
                 bool continuous = false);

 private:
  std::unique_ptr<SimulatedDevice> MakeSimulator(std::string* error) override;
  bool StartDevice(const SerialLinkOptions& link, std::string* error) override;
  void StopDevice() override;
  LinkStatus DeviceStatus() const override;
  bool InjectInput(const SimInjectRequest& request, SimulatedDevice& sim, std::string* error) override;

  bool continuous_;
  std::unique_ptr<JoystickDriver> driver_;
};

}  // namespace igms::devices
