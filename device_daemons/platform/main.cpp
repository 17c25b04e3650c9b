// igms-platformd: the MOLLY camera platform daemon (docs/devices.md, docs/protocol-devices.md).
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>

#include "common/config/exit_codes.h"
#include "common/config/lab_ports.h"
#include "common/config/process_options.h"
#include "common/net/process_server.h"
#include "device_daemons/platform/platform_daemon.h"

int main(int argc, char** argv) {
  namespace po = boost::program_options;
  po::options_description flags("Platform");
  igms::devices::AddDaemonFlags(&flags);
  flags.add_options()("poll-hz", po::value<double>(),
                      "orientation polling rate, at most 80 Hz (default 50)")(
      "backlash-deg", po::value<double>(),
      "simulator: gear backlash on pitch and roll (thesis: 1.59)");
  igms::devices::MollySimOptions sim;
  double poll_hz = 50;
  igms::devices::DaemonConfig daemon;
  int exit_code = 0;
  const auto process = igms::config::ParseProcessOptions(
      argc, argv, "platform",
      "The MOLLY camera platform daemon: orientation commands and readings over TCP.", flags,
      igms::devices::PlatformKeys(&sim, &poll_hz, &daemon), &exit_code);
  if (!process) return exit_code;
  try {
    igms::devices::DaemonOptions options;
    std::string error;
    if (!igms::devices::ReadDaemonOptions(*process, daemon, "platform", &options, &error)) {
      spdlog::error("{}", error);
      return igms::kExitUsage;
    }
    if (process->check_only) return igms::config::CheckPassed(*process);
    boost::asio::io_context io;
    igms::devices::PlatformDaemon daemon(
        io, options, igms::net::ServerOptionsFor(*process, igms::config::ports::kPlatform), sim,
        poll_hz);
    return igms::devices::RunDaemonProcess(
        io,
        [&](std::string* e) {
          if (!daemon.Start(e)) return false;
          spdlog::info("platform daemon on port {}", daemon.port());
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
