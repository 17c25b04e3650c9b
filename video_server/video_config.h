// The video server's section of the lab configuration (processes.NAME), docs/protocol-video.md:
//
//   video:
//     program: igms-video-server
//     port: 7301
//     backend: files            # files | camera, or one the program registered (sim)
//     sim: {scene: testbed.yaml, seed: 1}   # common/sim/capture/sim_capture.h
//     files: {left: left%02d.jpg, right: right%02d.jpg, first: 0, last: 9999, colour: false}
//     camera: {left: "0", right: "1", side_by_side: false, width: 0, height: 0, colour: false,
//              pace_fps: 0, frame_timeout_ms: 1000, retry_ms: 1000}
//     platform: platform        # follow this platform process's pose (platform_pose.h)
//     store_capacity: 16        # grabs kept
//     edge_threads: 2
//     edges: {sigma: 1.0607, low: 50, high: 150, l2_gradient: true}
//     encoding: png             # png | raw, when a request does not say
//     overlay_file: video-overlay.yaml
//     max_frame_bytes: 4194304  # largest request accepted
//
// Relative paths are relative to the configuration file's folder.
#pragma once

#include <memory>
#include <string>

#include "common/config/process_options.h"
#include "video_server/camera_capture.h"
#include "video_server/capture_backend.h"
#include "video_server/capture_registry.h"
#include "video_server/files_capture.h"
#include "video_server/video_service.h"

namespace igms::video {

// The options the keys above fill (VideoKeys binds them; ReadVideoConfig reads them).
struct VideoConfig {
  std::string backend = "files";
  FilesCaptureOptions files;    // left and right made absolute
  CameraCaptureOptions camera;  // a device path made absolute, an index as given
  VideoServiceOptions service;  // all but default_encoding, overlay_path and the calibration
  std::string encoding = "png";
  std::string overlay_file;  // absolute; empty: the overlay kept in memory only
  std::string platform;      // the platform process to follow (platform_pose.h)
};

// The keys above bound to `config`, the keys of the backends a program registered
// (capture_registry.h), and max_frame_bytes (net::ServerKeys), for ParseProcessOptions.
config::Keys VideoKeys(VideoConfig* config);

// The video options of process `process` (flags over keys over defaults). Throws
// config::ConfigError for a key of the wrong type.
VideoConfig ReadVideoConfig(const config::ProcessOptions& process);

// Builds the configured backend: files or camera, or one registered by the program
// (capture_registry.h). Errors name the key at fault, and an unknown backend's error names
// the available ones. Throws config::ConfigError for a key of the wrong type.
BackendChoice MakeConfiguredBackend(const config::ProcessOptions& process);

// The service options from the configuration; `error` set when they do not pass Check().
VideoServiceOptions ConfiguredServiceOptions(const config::ProcessOptions& process,
                                             std::string* error);

}  // namespace igms::video
