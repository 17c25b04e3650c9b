#include "device_daemons/joystick/joystick_daemon.h"

#include <algorithm>
#include <vector>

namespace igms::devices {

namespace {

// A list key's values into `out`; an empty list leaves `out` as it is.
template <class T, size_t N>
bool CopyList(const config::ProcessOptions& p, const std::string& sub, const std::vector<T>& values,
              std::array<T, N>* out, std::string* error) {
  if (values.empty()) return true;
  if (values.size() != N) {
    *error = p.Key(sub) + ": expected " + std::to_string(N) + " values, got " +
             std::to_string(values.size());
    return false;
  }
  std::copy(values.begin(), values.end(), out->begin());
  return true;
}

}  // namespace

config::Keys JoystickKeys(JoystickDaemonOptions* options, DaemonConfig* daemon) {
  config::Keys keys = DaemonKeys(daemon);
  keys.Bind("continuous", &options->continuous, "let the box stream ('C') instead of polling",
            "continuous");
  keys.Bind("gamepad", &options->gamepad_device,
            "read a Linux joystick or gamepad (e.g. /dev/input/js0) instead of a FlyBox",
            "gamepad");
  auto& map = options->gamepad_map;
  keys.Bind("gamepad_map.axes", &map.axes,
            "device axes of x, y, twist, lever 0, lever 1 (-1: unmapped)");
  keys.Bind("gamepad_map.invert", &map.invert, "5 booleans: which axes are inverted");
  keys.Bind("gamepad_map.buttons", &map.buttons, "the device buttons of FlyBox buttons 1-8");
  keys.Bind("gamepad_map.trigger", &map.trigger, "the device button of the trigger");
  return keys;
}

bool ReadGamepadMapping(const config::ProcessOptions& p, JoystickDaemonOptions* options,
                        std::string* error) {
  const auto& keys = options->gamepad_map;
  GamepadMapping m;
  if (!CopyList(p, "gamepad_map.axes", keys.axes, &m.axes, error) ||
      !CopyList(p, "gamepad_map.invert", keys.invert, &m.invert, error) ||
      !CopyList(p, "gamepad_map.buttons", keys.buttons, &m.buttons, error)) {
    return false;
  }
  m.trigger = keys.trigger;
  if (!m.Check(error)) {
    *error = p.Key("gamepad_map") + ": " + *error;
    return false;
  }
  options->mapping = m;
  return true;
}

JoystickDaemon::JoystickDaemon(boost::asio::io_context& io, DaemonOptions options,
                               net::ServerOptions server, JoystickDaemonOptions joystick)
    : DaemonBase(io, "joystick", "igms.devices.JoystickService", std::move(options),
                 std::move(server), FlyBoxSim::kMaxRateHz),
      joystick_(std::move(joystick)) {}

std::unique_ptr<SimulatedDevice> JoystickDaemon::MakeSimulator(std::string*) {
  return std::make_unique<FlyBoxSim>();
}

bool JoystickDaemon::StartDevice(const SerialLinkOptions& link, std::string* error) {
  if (joystick_.gamepad) {
    GamepadReaderOptions options;
    options.path = link.port;
    options.mapping = joystick_.mapping;
    options.backoff_min = link.backoff_min;
    options.backoff_max = link.backoff_max;
    if (!options.Check(error)) return false;
    gamepad_ = std::make_unique<GamepadReader>(
        io_, options, [this](const JoystickState& s) { hub().Publish(s); });
    gamepad_->Start();
    return true;
  }
  JoystickDriverOptions options;
  options.link = link;
  options.continuous = joystick_.continuous;
  if (!options.Check(error)) return false;
  driver_ = std::make_unique<JoystickDriver>(io_, options,
                                             [this](const JoystickState& s) { hub().Publish(s); });
  driver_->Start();
  return true;
}

void JoystickDaemon::StopDevice() {
  if (driver_) driver_->Stop();
  if (gamepad_) gamepad_->Stop();
}

LinkStatus JoystickDaemon::DeviceStatus() const {
  if (gamepad_) return gamepad_->status();
  return driver_ ? driver_->status() : LinkStatus();
}

bool JoystickDaemon::InjectInput(const SimInjectRequest& request, SimulatedDevice& sim,
                                 SimInjectResponse*, std::string* error) {
  if (!request.has_joystick()) {
    *error = "the joystick simulator takes a JoystickState (or a fault)";
    return false;
  }
  static_cast<FlyBoxSim&>(sim).Set(request.joystick());
  return true;
}

}  // namespace igms::devices
