// igms-viewerd: the BOOM viewer daemon (docs/devices.md, docs/protocol-devices.md).
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>
#include <sstream>
#include <tuple>
#include <vector>

#include "common/config/lab_ports.h"
#include "common/config/process_options.h"
#include "device_daemons/viewer/viewer_daemon.h"

int main(int argc, char** argv) {
  namespace po = boost::program_options;
  po::options_description flags("Viewer");
  igms::devices::AddDaemonFlags(&flags);
  flags.add_options()
      ("stream", po::bool_switch(), "let the viewer stream ('S') instead of polling it")
      ("poll-hz", po::value<double>(), "polling rate, at most 70 Hz (default 70)")
      ("path", po::value<std::string>(), "simulator: a head-motion path file")
      ("power-up", po::value<std::string>(), "simulator: the head's power-up pose in the site, \"x y z yaw pitch roll\" (metres, degrees)");
  int exit_code = 0;
  const auto process = igms::config::ParseProcessOptions(
      argc, argv, "viewer", "The BOOM viewer daemon: head pose and buttons to TCP readings.", flags, &exit_code);
  if (!process) return exit_code;
  try {
    igms::devices::DaemonOptions options;
    std::string error;
    if (!igms::devices::ReadDaemonOptions(*process, "viewer", &options, &error)) {
      spdlog::error("{}", error);
      return 2;
    }
    const auto& f = process->flags;
    igms::devices::ViewerDaemonOptions viewer;
    viewer.stream = f["stream"].as<bool>() || process->Get<bool>("stream", false);
    viewer.poll_hz = f.count("poll-hz") ? f["poll-hz"].as<double>() : process->Get<double>("poll_hz", 70.0);
    viewer.path_file = f.count("path") ? f["path"].as<std::string>() : process->Get<std::string>("path", "");
    std::vector<double> power_up = process->Get<std::vector<double>>("power_up", {});
    if (f.count("power-up")) {
      std::istringstream in(f["power-up"].as<std::string>());
      power_up.clear();
      for (double v; in >> v;) power_up.push_back(v);
    }
    if (!power_up.empty()) {
      if (power_up.size() != 6) {
        spdlog::error("the power-up pose takes 6 numbers: x y z (metres) yaw pitch roll (degrees)");
        return 2;
      }
      auto& p = viewer.sim.power_up;
      std::tie(p.x_m, p.y_m, p.z_m, p.yaw_deg, p.pitch_deg, p.roll_deg) =
          std::tie(power_up[0], power_up[1], power_up[2], power_up[3], power_up[4], power_up[5]);
    }
    boost::asio::io_context io;
    igms::net::ServerOptions server;
    server.name = process->name;
    server.bind_address = process->BindAddress();
    server.port = process->Port(igms::config::ports::kViewer);
    server.token = process->Token();
    igms::devices::ViewerDaemon daemon(io, options, server, viewer);
    return igms::devices::RunDaemonProcess(
        io,
        [&](std::string* e) {
          if (!daemon.Start(e)) return false;
          spdlog::info("viewer daemon on port {}", daemon.port());
          return true;
        },
        [&] { daemon.Stop(); });
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return 1;
  }
}
