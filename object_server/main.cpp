// igms-object-server: locates cylinders and boxes from the operator's marks on a video
// server's grab (docs/protocol-object.md). Configuration, processes.NAME:
//   object: {port: 7302, video: video, fetch_timeout_ms: 2000, cache_frames: 4}
// and lab.calibration (required) for the cameras.
#include <spdlog/spdlog.h>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <cstdio>
#include <fstream>

#include "common/calibration/calibration_file.h"
#include "common/calibration/calibration_hash.h"
#include "common/config/exit_codes.h"
#include "common/config/lab_ports.h"
#include "common/config/process_options.h"
#include "common/net/client.h"
#include "common/net/process_server.h"
#include "common/net/server.h"
#include "object_server/object_service.h"

namespace po = boost::program_options;

int main(int argc, char** argv) {
  try {
    po::options_description extra("Object server options");
    extra.add_options()("port-file", po::value<std::string>(),
                        "write the port listened on to this file once listening");
    igms::object::ObjectServiceOptions options;
    int exit_code = 0;
    auto process = igms::config::ParseProcessOptions(
        argc, argv, "object", "igms-object-server: cylinders and boxes from marks and a grab",
        extra, igms::object::ObjectKeys(&options), &exit_code);
    if (!process) return exit_code;

    const std::string& calibration_file = process->lab.calibration;
    if (calibration_file.empty()) {
      spdlog::critical("lab.calibration: the object server needs the cameras' calibration");
      return igms::kExitUsage;
    }
    const auto calibration = igms::calibration::LoadCalibration(calibration_file);
    if (!calibration.ok()) {
      spdlog::critical("lab.calibration: {}", calibration.error());
      return igms::kExitUsage;
    }
    options.ranger = igms::object::RangerInWorld(*calibration);
    options.platform = calibration->platform;
    options.ranger_mount = calibration->ranger;
    options.calibration_file = calibration_file;
    options.calibration_sha256 = igms::calibration::CalibrationHash(*calibration);
    if (std::string problem; !options.Check(&problem)) {
      spdlog::critical("{}: {}", process->Key(""), problem);
      return igms::kExitUsage;
    }
    const std::string& video_name = options.video_process;
    const std::string video_host = process->HostOf(video_name);
    const std::uint16_t video_port = process->PortOf(video_name);
    if (process->check_only) return igms::config::CheckPassed(*process);

    boost::asio::io_context io;
    igms::net::ClientOptions video_options;
    video_options.name = process->name;
    video_options.host = video_host;
    video_options.port = video_port;
    video_options.token = process->lab.token;
    video_options.max_frame_bytes = 64u << 20;  // a raw colour pair is about 1.5 MB
    // Locates fail at once while the video server is down, so a restarted one is retried
    // within a second rather than the client's default 5 s.
    video_options.max_backoff = std::chrono::milliseconds(1000);
    options.video = video_options.host + ":" + std::to_string(video_options.port);
    igms::net::Client video(io, video_options);

    igms::net::Server server(io,
                             igms::net::ServerOptionsFor(*process, igms::config::ports::kObject));
    igms::object::ObjectService service(video, calibration->left.Camera(),
                                        calibration->right.Camera(), options);
    service.Register(server);
    video.Start();
    server.Start();
    spdlog::info("listening on port {}; frames from {} at {}:{}", server.port(), video_name,
                 video_options.host, video_options.port);
    igms::net::WritePortFile(*process, server.port());
    const auto signals = igms::net::StopOnSignal(io, [&] {
      server.Stop();
      video.Stop();
      io.stop();
    });
    // The worker's CallSync needs the io context running on another thread than its own.
    io.run();
    return igms::kExitOk;
  } catch (const igms::config::ConfigError& e) {
    spdlog::critical("igms-object-server: {}", e.what());
    return igms::kExitUsage;
  } catch (const std::exception& e) {
    spdlog::critical("igms-object-server: {}", e.what());
    return igms::kExitFailure;
  }
}
