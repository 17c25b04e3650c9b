// igms-video-server: grabs stereo pairs, keeps them by frame id, detects their edges at once,
// streams live video and keeps the overlay settings (docs/protocol-video.md).
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <exception>
#include <fstream>
#include <iostream>
#include <memory>

#include "common/config/exit_codes.h"
#include "common/config/lab_ports.h"
#include "common/config/process_options.h"
#include "common/net/process_server.h"
#include "common/net/server.h"
#include "common/sim/capture/sim_capture.h"
#include "video_server/platform_pose.h"
#include "video_server/video_config.h"
#include "video_server/video_service.h"

namespace po = boost::program_options;

int main(int argc, char** argv) {
  // The program, not the library, offers `backend: sim`: the simulated site.
  igms::video::RegisterSimCapture();
  try {
    po::options_description extra("Video server options");
    extra.add_options()("port-file", po::value<std::string>(),
                        "write the port listened on to this file once listening");
    int exit_code = 0;
    igms::video::VideoConfig video;
    auto process = igms::config::ParseProcessOptions(
        argc, argv, "video", "igms-video-server: stereo grabs, edges, live video, overlay", extra,
        igms::video::VideoKeys(&video), &exit_code);
    if (!process) return exit_code;

    std::string error;
    igms::video::VideoServiceOptions options =
        igms::video::ConfiguredServiceOptions(*process, &error);
    if (!error.empty()) {
      spdlog::critical("{}", error);
      return igms::kExitUsage;
    }
    // A check opens no camera: the camera backend's keys are checked by their declarations.
    igms::video::BackendChoice backend;
    if (!process->check_only || video.backend != "camera") {
      backend = igms::video::MakeConfiguredBackend(*process);
      if (!backend.backend) {
        spdlog::critical("{}", backend.error);
        return igms::kExitUsage;
      }
    }
    auto overlay = igms::video::LoadOverlaySettings(options.overlay_path);
    if (!overlay.ok()) {
      spdlog::critical("{}", overlay.error());
      return igms::kExitUsage;
    }
    auto platform = igms::video::ConfiguredPlatformFollow(*process);
    if (!platform.ok()) {
      spdlog::critical("{}", platform.error());
      return igms::kExitUsage;
    }
    if (process->check_only) return igms::config::CheckPassed(*process);
    spdlog::info("backend {}; keeping {} grabs; edges sigma {:.3f} px, thresholds {}/{}",
                 backend.backend->Describe(), options.store_capacity, options.edges.sigma,
                 options.edges.low_threshold, options.edges.high_threshold);

    boost::asio::io_context io;
    std::unique_ptr<igms::video::PlatformPoseFollower> follower;
    igms::video::PoseSource pose;
    if (*platform) {
      follower = std::make_unique<igms::video::PlatformPoseFollower>(io, std::move(**platform));
      pose = [&follower] { return follower->Pose(); };
    }
    igms::net::Server server(io,
                             igms::net::ServerOptionsFor(*process, igms::config::ports::kVideo));
    igms::video::VideoService service(io, std::move(backend.backend), options, *overlay, pose);
    service.Register(server);
    if (follower) follower->Start();
    server.Start();
    igms::net::WritePortFile(*process, server.port());
    const auto signals = igms::net::StopOnSignal(io, [&] {
      server.Stop();
      if (follower) follower->Stop();
      io.stop();
    });
    io.run();
    return igms::kExitOk;
  } catch (const igms::config::ConfigError& e) {
    spdlog::critical("igms-video-server: {}", e.what());
    return igms::kExitUsage;
  } catch (const std::exception& e) {
    spdlog::critical("igms-video-server: {}", e.what());
    return igms::kExitFailure;
  }
}
