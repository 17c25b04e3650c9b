#include "video_server/video_config.h"

#include <spdlog/spdlog.h>

#include "common/calibration/calibration_file.h"
#include "common/calibration/calibration_hash.h"
#include "common/net/process_server.h"
#include "video_server/camera_capture.h"
#include "video_server/files_capture.h"

namespace igms::video {
namespace {

std::string PathKey(const config::ProcessOptions& process, const std::string& sub) {
  const std::string value = process.Get<std::string>(sub, "");
  // Numbered patterns and device indices pass through; paths are made absolute.
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

config::Keys VideoKeys() {
  using config::KeyType;
  config::Keys keys = net::ServerKeys();
  keys.Choice("backend", {"files", "camera", "sim"}, "files", "where the stereo pairs come from");
  keys.Path("sim.scene", "sim: the site's scene file (default: the thesis testbed)");
  keys.Add("sim.seed", KeyType::kInt, "", "sim: the sensor noise seed (default: the scene's)");
  keys.Add("files.left", KeyType::kString, "", "files: the left images, a numbered pattern");
  keys.Add("files.right", KeyType::kString, "", "files: the right images, a numbered pattern");
  keys.Add("files.first", KeyType::kInt, "0", "files: the first number");
  keys.Add("files.last", KeyType::kInt, "9999", "files: the last number");
  keys.Add("files.colour", KeyType::kBool, "false", "files: keep colour");
  keys.Add("camera.left", KeyType::kString, "0", "camera: the left camera (device or index)");
  keys.Add("camera.right", KeyType::kString, "1", "camera: the right camera (device or index)");
  keys.Add("camera.side_by_side", KeyType::kBool, "false",
           "camera: one device, pairs side by side");
  keys.Add("camera.width", KeyType::kInt, "0", "camera: frame width (0: the camera's)");
  keys.Add("camera.height", KeyType::kInt, "0", "camera: frame height (0: the camera's)");
  keys.Add("camera.colour", KeyType::kBool, "false", "camera: keep colour");
  keys.Add("camera.pace_fps", KeyType::kNumber, "0", "camera: grab at most this often (0: freely)");
  keys.Add("camera.frame_timeout_ms", KeyType::kInt, "1000",
           "camera: a frame later than this fails");
  keys.Add("camera.retry_ms", KeyType::kInt, "1000", "camera: reopen a lost camera this often");
  keys.Add("platform", KeyType::kString, "", "follow this platform process's pose");
  keys.Add("store_capacity", KeyType::kInt, "16", "grabs kept");
  keys.Add("edge_threads", KeyType::kInt, "2", "threads detecting edges");
  keys.Add("encode_threads", KeyType::kInt, "2", "threads encoding images");
  keys.Add("edges.sigma", KeyType::kNumber, "1.0607", "edges: Gaussian sigma in pixels");
  keys.Add("edges.low", KeyType::kNumber, "50", "edges: low hysteresis threshold");
  keys.Add("edges.high", KeyType::kNumber, "150", "edges: high hysteresis threshold");
  keys.Add("edges.l2_gradient", KeyType::kBool, "true", "edges: L2 gradient magnitude");
  keys.Choice("encoding", {"png", "raw"}, "png", "image encoding when a request does not say");
  keys.Add("overlay_file", KeyType::kOutputPath, "", "where the overlay settings are kept");
  return keys;
}

BackendChoice MakeConfiguredBackend(const config::ProcessOptions& process) {
  BackendChoice choice;
  const std::string backend = process.Get<std::string>("backend", "files");
  if (backend == "files") {
    FilesCaptureOptions files;
    files.left = PathKey(process, "files.left");
    files.right = PathKey(process, "files.right");
    files.first = process.Get<int>("files.first", files.first);
    files.last = process.Get<int>("files.last", files.last);
    files.colour = process.Get<bool>("files.colour", files.colour);
    FilesOpenResult open = OpenFilesCapture(files);
    choice.backend = std::move(open.backend);
    if (!choice.backend) choice.error = process.Key("files") + ": " + open.error;
  } else if (backend == "camera") {
    CameraCaptureOptions camera;
    camera.left = PathKey(process, "camera.left");
    camera.right = PathKey(process, "camera.right");
    camera.side_by_side = process.Get<bool>("camera.side_by_side", false);
    camera.width = process.Get<int>("camera.width", 0);
    camera.height = process.Get<int>("camera.height", 0);
    camera.colour = process.Get<bool>("camera.colour", false);
    camera.pace_fps = process.Get<double>("camera.pace_fps", 0.0);
    camera.frame_timeout =
        std::chrono::milliseconds(process.Get<int>("camera.frame_timeout_ms", 1000));
    camera.retry_interval = std::chrono::milliseconds(process.Get<int>("camera.retry_ms", 1000));
    std::string error;
    choice.backend = MakeCameraCapture(camera, &error);
    if (!choice.backend) choice.error = process.Key("camera") + ": " + error;
  } else if (const CaptureBackendFactory* factory = FindCaptureBackend(backend)) {
    choice = (*factory)(process);
  } else {
    choice.error = process.Key("backend") + ": unknown backend '" + backend + "' (" +
                   AvailableBackends() + ")";
  }
  return choice;
}

VideoServiceOptions ConfiguredServiceOptions(const config::ProcessOptions& process,
                                             std::string* error) {
  VideoServiceOptions options;
  options.store_capacity = static_cast<size_t>(
      std::max(0, process.Get<int>("store_capacity", static_cast<int>(options.store_capacity))));
  options.edge_threads = process.Get<int>("edge_threads", options.edge_threads);
  options.encode_threads = process.Get<int>("encode_threads", options.encode_threads);
  options.edges.sigma = process.Get<double>("edges.sigma", options.edges.sigma);
  options.edges.low_threshold = process.Get<double>("edges.low", options.edges.low_threshold);
  options.edges.high_threshold = process.Get<double>("edges.high", options.edges.high_threshold);
  options.edges.l2_gradient = process.Get<bool>("edges.l2_gradient", options.edges.l2_gradient);
  const std::string encoding = process.Get<std::string>("encoding", "png");
  if (encoding != "png" && encoding != "raw") {
    *error = process.Key("encoding") + ": must be png or raw, not '" + encoding + "'";
    return options;
  }
  options.default_encoding =
      encoding == "png" ? wire::ImageEncoding::kPng : wire::ImageEncoding::kRaw;
  const std::string overlay = process.Get<std::string>("overlay_file", "");
  options.overlay_path = overlay.empty() ? "" : process.config.ResolvePath(overlay);
  // The calibration's identity for GetStatus. The sim backend and the platform pose read
  // the file themselves and refuse a bad one; the other backends do not need it, so a file
  // that does not load only goes unreported.
  const std::string calibration_file = process.config.Get<std::string>("lab.calibration", "");
  if (!calibration_file.empty()) {
    const std::string path = process.config.ResolvePath(calibration_file);
    std::string why;
    if (const auto calibration = calibration::LoadCalibration(path, &why)) {
      options.calibration_file = path;
      options.calibration_sha256 = calibration::CalibrationHash(*calibration);
    } else {
      spdlog::warn("lab.calibration: {}; GetStatus reports no calibration", why);
    }
  }
  if (std::string problem; !options.Check(&problem)) {
    *error = process.Key("") + " " + problem;
  }
  return options;
}

}  // namespace igms::video
