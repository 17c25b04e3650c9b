#include "device_daemons/joystick/joystick_daemon.h"

namespace igms::devices {

JoystickDaemon::JoystickDaemon(boost::asio::io_context& io, DaemonOptions options,
                               net::ServerOptions server, bool continuous)
    : DaemonBase(io, "joystick", "igms.devices.JoystickService", std::move(options), std::move(server),
                 FlyBoxSim::kMaxRateHz),
      continuous_(continuous) {}

std::unique_ptr<SimulatedDevice> JoystickDaemon::MakeSimulator(std::string*) {
  return std::make_unique<FlyBoxSim>();
}

bool JoystickDaemon::StartDevice(const SerialLinkOptions& link, std::string* error) {
  JoystickDriverOptions options;
  options.link = link;
  options.continuous = continuous_;
  if (!options.Check(error)) return false;
  driver_ = std::make_unique<JoystickDriver>(io_, options, [this](const JoystickState& s) { hub().Publish(s); });
  driver_->Start();
  return true;
}

void JoystickDaemon::StopDevice() {
  if (driver_) driver_->Stop();
}

LinkStatus JoystickDaemon::DeviceStatus() const { return driver_ ? driver_->status() : LinkStatus(); }

bool JoystickDaemon::InjectInput(const SimInjectRequest& request, SimulatedDevice& sim, std::string* error) {
  if (!request.has_joystick()) {
    *error = "the joystick simulator takes a JoystickState (or a fault)";
    return false;
  }
  static_cast<FlyBoxSim&>(sim).Set(request.joystick());
  return true;
}

}  // namespace igms::devices
