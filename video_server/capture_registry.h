// Capture backends by name, chosen at run time by the lab configuration's `backend` key.
//
// The library builds `files` and `camera` itself (video_config.h). A program adds others by
// registering them before it reads the configuration: igms-video-server registers the
// simulated site's `sim` (common/sim/capture/sim_capture.h), so the simulation is linked
// into the program and never into this library.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/config/process_options.h"
#include "video_server/capture_backend.h"

namespace igms::video {

struct BackendChoice {
  std::unique_ptr<CaptureBackend> backend;
  std::string error;  // set when backend is empty; names the key at fault
};

// Builds a backend from process `process`'s section of the lab configuration.
using CaptureBackendFactory = std::function<BackendChoice(const config::ProcessOptions& process)>;

// Adds the backend `name`, replacing one of that name, and the keys its factory reads
// (declared for VideoKeys: checked and listed in --help like the library's own). Call before
// the configuration is read, from one thread (a program's main).
void RegisterCaptureBackend(const std::string& name, CaptureBackendFactory factory,
                            const config::Keys& keys = {});

// The keys of every registered backend, declared (not bound).
config::Keys CaptureBackendKeys();

// The backend registered as `name`, or nullptr.
const CaptureBackendFactory* FindCaptureBackend(const std::string& name);

// The backends this program can build, the built-in ones first: {"files", "camera", ...}.
std::vector<std::string> CaptureBackendNames();

}  // namespace igms::video
