#include "device_daemons/viewer/viewer_daemon.h"

#include <fstream>
#include <sstream>

namespace igms::devices {

config::Keys ViewerKeys(ViewerDaemonOptions* options, DaemonConfig* daemon) {
  config::Keys keys = DaemonKeys(daemon);
  keys.Bind("stream", &options->stream, "let the viewer stream ('S') instead of polling it",
            "stream");
  keys.Bind("poll_hz", &options->poll_hz, "polling rate, at most 70 Hz", "poll-hz");
  keys.Bind("path", &options->path_file, "simulator: a head-motion path file", "path");
  keys.Bind("power_up", &options->power_up,
            "simulator: the head's power-up pose in the site, [x, y, z, yaw, pitch, roll] "
            "(metres, degrees)",
            "power-up");
  return keys;
}

ViewerDaemon::ViewerDaemon(boost::asio::io_context& io, DaemonOptions options,
                           net::ServerOptions server, ViewerDaemonOptions viewer)
    : DaemonBase(io, "viewer", "igms.devices.ViewerService", std::move(options), std::move(server),
                 boom::kMaxRateHz),
      viewer_(std::move(viewer)) {}

std::unique_ptr<SimulatedDevice> ViewerDaemon::MakeSimulator(std::string* error) {
  auto sim = std::make_unique<ViewerSim>(viewer_.sim);
  if (!viewer_.path_file.empty()) {
    std::ifstream in(viewer_.path_file);
    if (!in) {
      *error = "cannot read the viewer path " + viewer_.path_file;
      return nullptr;
    }
    std::stringstream text;
    text << in.rdbuf();
    auto path = ParseViewerPath(text.str());
    if (!path.ok()) {
      *error = viewer_.path_file + ": " + path.error();
      return nullptr;
    }
    sim->SetPath(std::move(*path));
  }
  return sim;
}

bool ViewerDaemon::StartDevice(const SerialLinkOptions& link, std::string* error) {
  ViewerDriverOptions options;
  options.link = link;
  options.stream = viewer_.stream;
  options.poll_hz = viewer_.poll_hz;
  if (!options.Check(error)) return false;
  driver_ = std::make_unique<ViewerDriver>(io_, options,
                                           [this](const ViewerState& s) { hub().Publish(s); });
  driver_->Start();
  return true;
}

void ViewerDaemon::StopDevice() {
  if (driver_) driver_->Stop();
}

LinkStatus ViewerDaemon::DeviceStatus() const { return driver_ ? driver_->status() : LinkStatus(); }

bool ViewerDaemon::InjectInput(const SimInjectRequest& request, SimulatedDevice& sim,
                               SimInjectResponse*, std::string* error) {
  auto& viewer = static_cast<ViewerSim&>(sim);
  if (request.has_viewer_buttons()) {  // the buttons alone: the pose or path goes on
    viewer.SetButtons(request.viewer_buttons().button_left(),
                      request.viewer_buttons().button_right());
    return true;
  }
  if (!request.has_viewer()) {
    *error = "the viewer simulator takes a ViewerState or ViewerButtons (or a fault)";
    return false;
  }
  const ViewerState& v = request.viewer();
  boom::Pose pose;
  pose.x_m = v.x_m();
  pose.y_m = v.y_m();
  pose.z_m = v.z_m();
  pose.yaw_deg = v.yaw_deg();
  pose.pitch_deg = v.pitch_deg();
  pose.roll_deg = v.roll_deg();
  viewer.SetSteady(pose);
  viewer.SetButtons(v.button_left(), v.button_right());
  return true;
}

}  // namespace igms::devices
