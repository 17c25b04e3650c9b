#include "video_server/video_config.h"

#include <spdlog/spdlog.h>

#include "common/calibration/calibration_file.h"
#include "common/calibration/calibration_hash.h"
#include "common/net/process_server.h"

namespace igms::video {
namespace {

// Numbered patterns and device indices pass through; paths are made absolute.
std::string ResolveUnlessIndex(const config::ProcessOptions& process, const std::string& value) {
  if (value.empty() ||
      (value.size() <= 4 && value.find_first_not_of("0123456789") == std::string::npos)) {
    return value;
  }
  return process.config.ResolvePath(value);
}

// "files, camera or sim".
std::string AvailableBackends() {
  const std::vector<std::string> names = CaptureBackendNames();
  std::string list;
  for (size_t i = 0; i < names.size(); ++i) {
    if (i > 0) list += i + 1 == names.size() ? " or " : ", ";
    list += names[i];
  }
  return list;
}

}  // namespace

config::Keys VideoKeys(VideoConfig* c) {
  using config::KeyType;
  config::Keys keys = net::ServerKeys();
  keys.BindChoice("backend", &c->backend, {"files", "camera", "sim"},
                  "where the stereo pairs come from");
  keys.Bind("files.left", &c->files.left, "files: the left images, a numbered pattern");
  keys.Bind("files.right", &c->files.right, "files: the right images, a numbered pattern");
  keys.Bind("files.first", &c->files.first, "files: the first number");
  keys.Bind("files.last", &c->files.last, "files: the last number");
  keys.Bind("files.colour", &c->files.colour, "files: keep colour");
  keys.Bind("camera.left", &c->camera.left, "camera: the left camera (device or index)");
  keys.Bind("camera.right", &c->camera.right, "camera: the right camera (device or index)");
  keys.Bind("camera.side_by_side", &c->camera.side_by_side,
            "camera: one device, pairs side by side");
  keys.Bind("camera.width", &c->camera.width, "camera: frame width (0: the camera's)");
  keys.Bind("camera.height", &c->camera.height, "camera: frame height (0: the camera's)");
  keys.Bind("camera.colour", &c->camera.colour, "camera: keep colour");
  keys.Bind("camera.pace_fps", &c->camera.pace_fps, "camera: grab at most this often (0: freely)");
  keys.Bind("camera.frame_timeout_ms", &c->camera.frame_timeout,
            "camera: a frame later than this fails");
  keys.Bind("camera.retry_ms", &c->camera.retry_interval,
            "camera: reopen a lost camera this often");
  keys.Bind("platform", &c->platform, "follow this platform process's pose");
  keys.Bind("store_capacity", &c->service.store_capacity, "grabs kept");
  keys.Bind("edge_threads", &c->service.edge_threads, "threads detecting edges");
  keys.Bind("encode_threads", &c->service.encode_threads, "threads encoding images");
  keys.Bind("edges.sigma", &c->service.edges.sigma, "edges: Gaussian sigma in pixels");
  keys.Bind("edges.low", &c->service.edges.low_threshold, "edges: low hysteresis threshold");
  keys.Bind("edges.high", &c->service.edges.high_threshold, "edges: high hysteresis threshold");
  keys.Bind("edges.l2_gradient", &c->service.edges.l2_gradient, "edges: L2 gradient magnitude");
  keys.BindChoice("encoding", &c->encoding, {"png", "raw"},
                  "image encoding when a request does not say");
  keys.BindPath("overlay_file", &c->overlay_file, "where the overlay settings are kept", "",
                KeyType::kOutputPath);
  keys.Merge(CaptureBackendKeys());
  return keys;
}

VideoConfig ReadVideoConfig(const config::ProcessOptions& process) {
  VideoConfig c;
  VideoKeys(&c).Read(process);
  c.files.left = ResolveUnlessIndex(process, c.files.left);
  c.files.right = ResolveUnlessIndex(process, c.files.right);
  c.camera.left = ResolveUnlessIndex(process, c.camera.left);
  c.camera.right = ResolveUnlessIndex(process, c.camera.right);
  return c;
}

BackendChoice MakeConfiguredBackend(const config::ProcessOptions& process) {
  BackendChoice choice;
  const VideoConfig c = ReadVideoConfig(process);
  if (c.backend == "files") {
    FilesOpenResult open = OpenFilesCapture(c.files);
    choice.backend = std::move(open.backend);
    if (!choice.backend) choice.error = process.Key("files") + ": " + open.error;
  } else if (c.backend == "camera") {
    std::string error;
    choice.backend = MakeCameraCapture(c.camera, &error);
    if (!choice.backend) choice.error = process.Key("camera") + ": " + error;
  } else if (const CaptureBackendFactory* factory = FindCaptureBackend(c.backend)) {
    choice = (*factory)(process);
  } else {
    choice.error = process.Key("backend") + ": unknown backend '" + c.backend + "' (" +
                   AvailableBackends() + ")";
  }
  return choice;
}

VideoServiceOptions ConfiguredServiceOptions(const config::ProcessOptions& process,
                                             std::string* error) {
  const VideoConfig c = ReadVideoConfig(process);
  VideoServiceOptions options = c.service;
  if (c.encoding != "png" && c.encoding != "raw") {
    *error = process.Key("encoding") + ": must be png or raw, not '" + c.encoding + "'";
    return options;
  }
  options.default_encoding =
      c.encoding == "png" ? wire::ImageEncoding::kPng : wire::ImageEncoding::kRaw;
  options.overlay_path = c.overlay_file;
  // The calibration's identity for GetStatus. The sim backend and the platform pose read
  // the file themselves and refuse a bad one; the other backends do not need it, so a file
  // that does not load only goes unreported.
  if (!process.lab.calibration.empty()) {
    const std::string& path = process.lab.calibration;
    if (const auto calibration = calibration::LoadCalibration(path); calibration.ok()) {
      options.calibration_file = path;
      options.calibration_sha256 = calibration::CalibrationHash(*calibration);
    } else {
      spdlog::warn("lab.calibration: {}; GetStatus reports no calibration", calibration.error());
    }
  }
  if (std::string problem; !options.Check(&problem)) {
    *error = process.Key("") + " " + problem;
  }
  return options;
}

}  // namespace igms::video
