// igms-platformd: the MOLLY camera platform daemon (docs/devices.md, docs/protocol-devices.md).
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>

#include "common/config/lab_ports.h"
#include "common/config/process_options.h"
#include "device_daemons/platform/platform_daemon.h"

int main(int argc, char** argv) {
  namespace po = boost::program_options;
  po::options_description flags("Platform");
  igms::devices::AddDaemonFlags(&flags);
  flags.add_options()
      ("poll-hz", po::value<double>(), "orientation polling rate, at most 80 Hz (default 50)")
      ("backlash-deg", po::value<double>(), "simulator: gear backlash on pitch and roll (thesis: 1.59)");
  int exit_code = 0;
  const auto process = igms::config::ParseProcessOptions(
      argc, argv, "platform", "The MOLLY camera platform daemon: orientation commands and readings over TCP.",
      flags, &exit_code);
  if (!process) return exit_code;
  try {
    igms::devices::DaemonOptions options;
    std::string error;
    if (!igms::devices::ReadDaemonOptions(*process, "platform", &options, &error)) {
      spdlog::error("{}", error);
      return 2;
    }
    const auto& f = process->flags;
    igms::devices::MollySimOptions sim;
    sim.backlash_deg = f.count("backlash-deg") ? f["backlash-deg"].as<double>() : process->Get<double>("backlash_deg", 0.0);
    const double poll_hz = f.count("poll-hz") ? f["poll-hz"].as<double>() : process->Get<double>("poll_hz", 50.0);
    boost::asio::io_context io;
    igms::net::ServerOptions server;
    server.name = process->name;
    server.bind_address = process->BindAddress();
    server.port = process->Port(igms::config::ports::kPlatform);
    server.token = process->Token();
    igms::devices::PlatformDaemon daemon(io, options, server, sim, poll_hz);
    return igms::devices::RunDaemonProcess(
        io,
        [&](std::string* e) {
          if (!daemon.Start(e)) return false;
          spdlog::info("platform daemon on port {}", daemon.port());
          return true;
        },
        [&] { daemon.Stop(); });
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return 1;
  }
}
