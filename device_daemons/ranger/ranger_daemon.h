// igms-rangerd's body: the ranger driver (or its simulator, or a replay) behind
// igms.devices.RangerService (Range: one measurement on request; Live; Status) and
// igms.devices.SimService.Inject (a RangerState as a fixed answer: valid with range_in, or
// no echo when not valid; valid with range_in 0 ends the override; a PlatformState as the
// platform's pose, in encoder ticks). The simulator ranges the world the program registered
// (ranger_site.h; the simulated site in igms-rangerd): scene_file (default: the thesis
// testbed) from the mount of calibration_file. With follow_platform_port the simulator's beam turns
// with the camera platform: it subscribes to that daemon's PlatformService.Live (reconnecting when
// the platform daemon restarts) and feeds the reached orientation to the simulator. See
// daemon_base.h.
#pragma once

#include "common/net/client.h"
#include "device_daemons/ranger/ranger_driver.h"
#include "device_daemons/ranger/ranger_sim.h"
#include "device_daemons/serial/daemon_base.h"

namespace igms::devices {

struct RangerDaemonOptions {
  double poll_hz = 0;
  std::string scene_file;        // empty: the thesis testbed (common/sim/testbed.h)
  std::string calibration_file;  // empty: the sensor between the scene's cameras, no platform
  std::string platform;          // the platform process whose pose turns the beam (simulator)
  std::string platform_host = "127.0.0.1";
  uint16_t follow_platform_port = 0;  // 0: the beam stays where it is
  std::string token;                  // the lab token, for the platform daemon
};

// The ranger's keys (processes.NAME): the daemon's shared ones (DaemonKeys, bound to
// `daemon`), and poll_hz, scene, calibration and platform bound to `options` (the main finds
// the platform's port).
config::Keys RangerKeys(RangerDaemonOptions* options, DaemonConfig* daemon);

class RangerDaemon : public DaemonBase<RangerState> {
 public:
  RangerDaemon(boost::asio::io_context& io, DaemonOptions options, net::ServerOptions server,
               RangerDaemonOptions ranger = {});
  ~RangerDaemon() override;

 private:
  std::unique_ptr<SimulatedDevice> MakeSimulator(std::string* error) override;
  bool StartDevice(const SerialLinkOptions& link, std::string* error) override;
  void StopDevice() override;
  LinkStatus DeviceStatus() const override;
  bool InjectInput(const SimInjectRequest& request, SimulatedDevice& sim,
                   SimInjectResponse* response, std::string* error) override;
  void RegisterMethods(net::Server& server) override;

  RangerDaemonOptions ranger_;
  std::unique_ptr<RangerDriver> driver_;
  std::unique_ptr<net::Client> platform_;
};

}  // namespace igms::devices
