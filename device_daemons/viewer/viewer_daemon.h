// igms-viewerd's body: the BOOM driver (or its simulator, or a replay) behind
// igms.devices.ViewerService (Live, Status) and igms.devices.SimService.Inject, which takes
// a ViewerState as a steady head pose in the site and the handle buttons. The simulator can also
// follow a path file (viewer_sim.h). See daemon_base.h.
#pragma once

#include "device_daemons/serial/daemon_base.h"
#include "device_daemons/viewer/viewer_driver.h"
#include "device_daemons/viewer/viewer_sim.h"

namespace igms::devices {

struct ViewerDaemonOptions {
  bool stream = false;  // the viewer streams instead of being polled
  double poll_hz = boom::kMaxRateHz;
  std::string path_file;  // simulator: scripted head motion
  ViewerSimOptions sim;   // simulator: the head's power-up pose in the site
  // The power_up key or flag: x y z (metres) yaw pitch roll (degrees), or empty; the main
  // checks it and sets sim.power_up from it.
  std::vector<double> power_up;
};

// The viewer's keys (processes.NAME): the daemon's shared ones (DaemonKeys, bound to
// `daemon`), stream, poll_hz, path and power_up (bound to `options`).
config::Keys ViewerKeys(ViewerDaemonOptions* options, DaemonConfig* daemon);

class ViewerDaemon : public DaemonBase<ViewerState> {
 public:
  ViewerDaemon(boost::asio::io_context& io, DaemonOptions options, net::ServerOptions server,
               ViewerDaemonOptions viewer = {});

 private:
  std::unique_ptr<SimulatedDevice> MakeSimulator(std::string* error) override;
  bool StartDevice(const SerialLinkOptions& link, std::string* error) override;
  void StopDevice() override;
  LinkStatus DeviceStatus() const override;
  bool InjectInput(const SimInjectRequest& request, SimulatedDevice& sim,
                   SimInjectResponse* response, std::string* error) override;

  ViewerDaemonOptions viewer_;
  std::unique_ptr<ViewerDriver> driver_;
};

}  // namespace igms::devices
