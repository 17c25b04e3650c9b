#include "device_daemons/joystick/joystick_daemon.h"

#include <algorithm>
#include <vector>

namespace igms::devices {

namespace {

template <class T, size_t N>
bool ReadList(const config::ProcessOptions& p, const std::string& sub, std::array<T, N>* out,
              std::string* error) {
  const std::vector<T> values = p.Get<std::vector<T>>(sub, {});
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

config::Keys JoystickKeys(JoystickDaemonOptions* options) {
  using config::KeyType;
  config::Keys keys = DaemonKeys();
  keys.Bind("continuous", &options->continuous, "let the box stream ('C') instead of polling",
            "continuous");
  keys.Bind("gamepad", &options->gamepad_device,
            "read a Linux joystick or gamepad (e.g. /dev/input/js0) instead of a FlyBox",
            "gamepad");
  keys.Add("gamepad_map.axes", KeyType::kList, "",
           "device axes of x, y, twist, lever 0, lever 1 (-1: unmapped)");
  keys.Add("gamepad_map.invert", KeyType::kList, "", "5 booleans: which axes are inverted");
  keys.Add("gamepad_map.buttons", KeyType::kList, "", "the device buttons of FlyBox buttons 1-8");
  keys.Add("gamepad_map.trigger", KeyType::kInt, "", "the device button of the trigger");
  return keys;
}

bool ReadGamepadMapping(const config::ProcessOptions& p, GamepadMapping* mapping,
                        std::string* error) {
  GamepadMapping m;
  if (!ReadList(p, "gamepad_map.axes", &m.axes, error) ||
      !ReadList(p, "gamepad_map.invert", &m.invert, error) ||
      !ReadList(p, "gamepad_map.buttons", &m.buttons, error)) {
    return false;
  }
  m.trigger = p.Get<int>("gamepad_map.trigger", m.trigger);
  if (!m.Check(error)) {
    *error = p.Key("gamepad_map") + ": " + *error;
    return false;
  }
  *mapping = m;
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
