// igms-rangerd: the ultrasonic ranger daemon (docs/devices.md, docs/protocol-devices.md).
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>

#include "common/config/exit_codes.h"
#include "common/config/lab_ports.h"
#include "common/config/process_options.h"
#include "common/net/process_server.h"
#include "common/sim/ranger/site_ranger.h"
#include "device_daemons/ranger/ranger_daemon.h"

int main(int argc, char** argv) {
  // The program, not the library, gives `source: simulate` its world: the simulated site.
  igms::devices::RegisterSiteRanger();
  namespace po = boost::program_options;
  po::options_description flags("Ranger");
  igms::devices::AddDaemonFlags(&flags);
  flags.add_options()(
      "poll-hz", po::value<double>(),
      "also range continuously at this rate, at most 6 Hz (default: on request only)")(
      "scene", po::value<std::string>(),
      "simulator: the site's scene file (default: the thesis testbed)")(
      "calibration", po::value<std::string>(),
      "simulator: the calibration file with the ranger's mount and the platform model (default: "
      "lab.calibration)")("follow-platform", po::value<uint16_t>(),
                          "simulator: turn the beam with the platform daemon on this port "
                          "(default: the process named by processes.NAME.platform)");
  igms::devices::RangerDaemonOptions ranger;
  igms::devices::DaemonConfig daemon;
  int exit_code = 0;
  const auto process = igms::config::ParseProcessOptions(
      argc, argv, "ranger", "The ultrasonic ranger daemon: ranges on request over TCP.", flags,
      igms::devices::RangerKeys(&ranger, &daemon), &exit_code);
  if (!process) return exit_code;
  try {
    igms::devices::DaemonOptions options;
    std::string error;
    if (!igms::devices::ReadDaemonOptions(*process, daemon, "ranger", &options, &error)) {
      spdlog::error("{}", error);
      return igms::kExitUsage;
    }
    const auto& f = process->flags;
    if (ranger.calibration_file.empty() && !f.count("calibration")) {
      ranger.calibration_file = process->lab.calibration;
    }
    const std::string& platform_name = ranger.platform;
    if (f.count("follow-platform")) {
      ranger.follow_platform_port = f["follow-platform"].as<uint16_t>();
    } else if (!platform_name.empty() && options.source == igms::devices::SourceKind::kSimulate) {
      if (!process->config.Has("processes." + platform_name + ".port")) {
        spdlog::error("{}: no process named {} in the lab configuration", process->Key("platform"),
                      platform_name);
        return igms::kExitUsage;
      }
      ranger.platform_host = process->HostOf(platform_name);
      ranger.follow_platform_port = process->PortOf(platform_name);
    }
    ranger.token = process->lab.token;
    if (process->check_only) return igms::config::CheckPassed(*process);
    boost::asio::io_context io;
    igms::devices::RangerDaemon daemon(
        io, options, igms::net::ServerOptionsFor(*process, igms::config::ports::kRanger), ranger);
    return igms::devices::RunDaemonProcess(
        io,
        [&](std::string* e) {
          if (!daemon.Start(e)) return false;
          spdlog::info("ranger daemon on port {}", daemon.port());
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
