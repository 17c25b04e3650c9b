// igms-platformd's body: the MOLLY driver (or its simulator, or a replay) behind
// igms.devices.PlatformService (SetOrientation and ResetZero, answered once the platform
// acknowledges, from one controlling client at a time (platform_control.h); Live; Status,
// which names that client) and igms.devices.SimService.Inject (faults only). See
// daemon_base.h.
#pragma once

#include "device_daemons/platform/molly_sim.h"
#include "device_daemons/platform/platform_control.h"
#include "device_daemons/platform/platform_driver.h"
#include "device_daemons/serial/daemon_base.h"

namespace igms::devices {

// The platform's keys (processes.NAME): the daemon's shared ones (DaemonKeys, bound to
// `daemon`), poll_hz and backlash_deg (bound to `poll_hz` and `sim`).
config::Keys PlatformKeys(MollySimOptions* sim, double* poll_hz, DaemonConfig* daemon);

class PlatformDaemon : public DaemonBase<PlatformState> {
 public:
  PlatformDaemon(boost::asio::io_context& io, DaemonOptions options, net::ServerOptions server,
                 MollySimOptions sim = {}, double poll_hz = 50);

 private:
  std::unique_ptr<SimulatedDevice> MakeSimulator(std::string* error) override;
  bool StartDevice(const SerialLinkOptions& link, std::string* error) override;
  void StopDevice() override;
  LinkStatus DeviceStatus() const override;
  bool InjectInput(const SimInjectRequest& request, SimulatedDevice& sim,
                   SimInjectResponse* response, std::string* error) override;
  void RegisterMethods(net::Server& server) override;

  MollySimOptions sim_options_;
  double poll_hz_;
  std::unique_ptr<PlatformDriver> driver_;
  PlatformControl control_;
};

}  // namespace igms::devices
