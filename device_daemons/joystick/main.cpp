// igms-joystickd: the FlyBox joystick daemon (docs/devices.md, docs/protocol-devices.md).
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>

#include "common/config/process_options.h"
#include "device_daemons/joystick/joystick_daemon.h"

int main(int argc, char** argv) {
  namespace po = boost::program_options;
  po::options_description flags("Joystick");
  igms::devices::AddDaemonFlags(&flags);
  flags.add_options()("continuous", po::bool_switch(), "let the box stream ('C') instead of polling");
  int exit_code = 0;
  const auto process = igms::config::ParseProcessOptions(
      argc, argv, "joystick", "The FlyBox joystick daemon: CerealBox protocol to TCP readings.", flags, &exit_code);
  if (!process) return exit_code;
  try {
    igms::devices::DaemonOptions options;
    std::string error;
    if (!igms::devices::ReadDaemonOptions(*process, "joystick", &options, &error)) {
      spdlog::error("{}", error);
      return 2;
    }
    boost::asio::io_context io;
    igms::net::ServerOptions server;
    server.name = process->name;
    server.bind_address = process->BindAddress();
    server.port = process->Port(7310);
    server.token = process->Token();
    igms::devices::JoystickDaemon daemon(io, options, server,
                                         process->flags["continuous"].as<bool>() || process->Get<bool>("continuous", false));
    return igms::devices::RunDaemonProcess(
        io,
        [&](std::string* e) {
          if (!daemon.Start(e)) return false;
          spdlog::info("joystick daemon on port {}", daemon.port());
          return true;
        },
        [&] { daemon.Stop(); });
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return 1;
  }
}
