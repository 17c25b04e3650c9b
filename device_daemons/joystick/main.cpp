// igms-joystickd: the FlyBox joystick daemon (docs/devices.md, docs/protocol-devices.md).
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>

#include "common/config/exit_codes.h"
#include "common/config/lab_ports.h"
#include "common/config/process_options.h"
#include "common/net/process_server.h"
#include "device_daemons/joystick/joystick_daemon.h"

int main(int argc, char** argv) {
  namespace po = boost::program_options;
  po::options_description flags("Joystick");
  igms::devices::AddDaemonFlags(&flags);
  flags.add_options()("continuous", po::bool_switch(),
                      "let the box stream ('C') instead of polling")(
      "gamepad", po::value<std::string>(),
      "read a Linux joystick or gamepad (e.g. /dev/input/js0) instead of a FlyBox");
  igms::devices::JoystickDaemonOptions joystick;
  igms::devices::DaemonConfig daemon;
  int exit_code = 0;
  const auto process = igms::config::ParseProcessOptions(
      argc, argv, "joystick", "The FlyBox joystick daemon: CerealBox protocol to TCP readings.",
      flags, igms::devices::JoystickKeys(&joystick, &daemon), &exit_code);
  if (!process) return exit_code;
  try {
    // A gamepad is the source when named by the flag, or by the configuration unless a
    // flag names another source; it stands where a serial port would.
    const auto& f = process->flags;
    const bool other_flag = f.count("serial") || f["simulate"].as<bool>() || f.count("replay");
    std::string gamepad = joystick.gamepad_device;  // the flag, else the key
    if (other_flag && !f.count("gamepad")) gamepad.clear();
    if (!gamepad.empty()) {  // over the keys; a source flag still counts (and is one too many)
      if (!f.count("serial")) daemon.serial = gamepad;
      if (!f.count("replay")) daemon.replay.clear();
    }
    igms::devices::DaemonOptions options;
    std::string error;
    if (!igms::devices::ReadDaemonOptions(*process, daemon, "joystick", &options, &error)) {
      spdlog::error("{}", error);
      return igms::kExitUsage;
    }
    joystick.gamepad = !gamepad.empty();
    if (!igms::devices::ReadGamepadMapping(*process, &joystick, &error)) {
      spdlog::error("{}", error);
      return igms::kExitUsage;
    }
    if (process->check_only) return igms::config::CheckPassed(*process);
    boost::asio::io_context io;
    igms::devices::JoystickDaemon daemon(
        io, options, igms::net::ServerOptionsFor(*process, igms::config::ports::kJoystick),
        joystick);
    return igms::devices::RunDaemonProcess(
        io,
        [&](std::string* e) {
          if (!daemon.Start(e)) return false;
          spdlog::info("joystick daemon on port {}", daemon.port());
          return true;
        },
        [&] { daemon.Stop(); });
  } catch (const igms::config::ConfigError& e) {
    spdlog::error("{}", e.what());
    return igms::kExitUsage;
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return igms::kExitFailure;
  }
}
