// igms-video-server: grabs stereo pairs, keeps them by frame id, detects their edges at once,
// streams live video and keeps the overlay settings (docs/protocol-video.md).
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <exception>
#include <fstream>
#include <iostream>

#include "common/config/process_options.h"
#include "common/net/server.h"
#include "video_server/video_config.h"
#include "video_server/video_service.h"

namespace po = boost::program_options;

int main(int argc, char** argv) {
  try {
    po::options_description extra("Video server options");
    extra.add_options()("port-file", po::value<std::string>(),
                        "write the port listened on to this file once listening");
    int exit_code = 0;
    auto process = igms::config::ParseProcessOptions(
        argc, argv, "video", "igms-video-server: stereo grabs, edges, live video, overlay",
        extra, &exit_code);
    if (!process) return exit_code;

    std::string error;
    igms::video::VideoServiceOptions options =
        igms::video::ConfiguredServiceOptions(*process, &error);
    if (!error.empty()) {
      spdlog::critical("{}", error);
      return 2;
    }
    igms::video::BackendChoice backend = igms::video::MakeConfiguredBackend(*process);
    if (!backend.backend) {
      spdlog::critical("{}", backend.error);
      return 2;
    }
    auto overlay = igms::video::LoadOverlaySettings(options.overlay_path, &error);
    if (!overlay) {
      spdlog::critical("{}", error);
      return 2;
    }
    spdlog::info("backend {}; keeping {} grabs; edges sigma {:.3f} px, thresholds {}/{}",
                 backend.backend->Describe(), options.store_capacity, options.edges.sigma,
                 options.edges.low_threshold, options.edges.high_threshold);

    boost::asio::io_context io;
    igms::net::ServerOptions server_options;
    server_options.name = process->name;
    server_options.bind_address = process->BindAddress();
    server_options.port = process->Port(0);
    server_options.token = process->Token();
    server_options.max_frame_bytes =
        process->Get<std::size_t>("max_frame_bytes", server_options.max_frame_bytes);
    igms::net::Server server(io, server_options);
    igms::video::VideoService service(io, std::move(backend.backend), options, *overlay);
    service.Register(server);
    server.Start();
    if (process->flags.count("port-file")) {
      const std::string path = process->flags["port-file"].as<std::string>();
      std::ofstream(path + ".tmp") << server.port() << "\n";
      std::rename((path + ".tmp").c_str(), path.c_str());
    }
    boost::asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&](const boost::system::error_code&, int signal) {
      spdlog::info("signal {}: shutting down", signal);
      server.Stop();
      io.stop();
    });
    io.run();
    return 0;
  } catch (const std::exception& e) {
    spdlog::critical("igms-video-server: {}", e.what());
    return 1;
  }
}
