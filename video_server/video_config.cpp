#include "video_server/video_config.h"

#include "video_server/camera_capture.h"
#include "video_server/files_capture.h"

namespace igms::video {
namespace {

std::string PathKey(const config::ProcessOptions& process, const std::string& sub) {
  const std::string value = process.Get<std::string>(sub, "");
  // Numbered patterns and device indices pass through; paths are made absolute.
  if (value.empty() || (value.size() <= 4 && value.find_first_not_of("0123456789") == std::string::npos)) {
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
    camera.frame_timeout = std::chrono::milliseconds(process.Get<int>("camera.frame_timeout_ms", 1000));
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
  if (std::string problem = options.Check(); !problem.empty()) {
    *error = process.Key("") + " " + problem;
  }
  return options;
}

}  // namespace igms::video
