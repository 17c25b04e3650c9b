// igms-viewerd: the BOOM viewer daemon (docs/devices.md, docs/protocol-devices.md).
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>
#include <tuple>
#include <vector>

#include "common/config/exit_codes.h"
#include "common/config/lab_ports.h"
#include "common/config/process_options.h"
#include "common/net/process_server.h"
#include "device_daemons/viewer/viewer_daemon.h"

int main(int argc, char** argv) {
  namespace po = boost::program_options;
  po::options_description flags("Viewer");
  igms::devices::AddDaemonFlags(&flags);
  flags.add_options()("stream", po::bool_switch(),
                      "let the viewer stream ('S') instead of polling it")(
      "poll-hz", po::value<double>(), "polling rate, at most 70 Hz (default 70)")(
      "path", po::value<std::string>(), "simulator: a head-motion path file")(
      "power-up", po::value<std::string>(),
      "simulator: the head's power-up pose in the site, \"x y z yaw pitch roll\" (metres, "
      "degrees)");
  igms::devices::ViewerDaemonOptions viewer;
  igms::devices::DaemonConfig daemon;
  int exit_code = 0;
  const auto process = igms::config::ParseProcessOptions(
      argc, argv, "viewer", "The BOOM viewer daemon: head pose and buttons to TCP readings.", flags,
      igms::devices::ViewerKeys(&viewer, &daemon), &exit_code);
  if (!process) return exit_code;
  try {
    igms::devices::DaemonOptions options;
    std::string error;
    if (!igms::devices::ReadDaemonOptions(*process, daemon, "viewer", &options, &error)) {
      spdlog::error("{}", error);
      return igms::kExitUsage;
    }
    const std::vector<double>& power_up = viewer.power_up;
    if (!power_up.empty()) {
      if (power_up.size() != 6) {
        spdlog::error("the power-up pose takes 6 numbers: x y z (metres) yaw pitch roll (degrees)");
        return igms::kExitUsage;
      }
      auto& p = viewer.sim.power_up;
      std::tie(p.x_m, p.y_m, p.z_m, p.yaw_deg, p.pitch_deg, p.roll_deg) =
          std::tie(power_up[0], power_up[1], power_up[2], power_up[3], power_up[4], power_up[5]);
    }
    if (process->check_only) return igms::config::CheckPassed(*process);
    boost::asio::io_context io;
    igms::devices::ViewerDaemon daemon(
        io, options, igms::net::ServerOptionsFor(*process, igms::config::ports::kViewer), viewer);
    return igms::devices::RunDaemonProcess(
        io,
        [&](std::string* e) {
          if (!daemon.Start(e)) return false;
          spdlog::info("viewer daemon on port {}", daemon.port());
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
