// The video server's `sim` capture backend: the simulated site (common/sim) rendered as a
// stereo pair. It lives with the simulation, not in the video server's library: a program
// that offers it calls RegisterSimCapture() (igms-video-server does), which adds it to the
// backends chosen at run time (video_server/capture_registry.h).
//
// Configuration (processes.NAME of the lab configuration, docs/protocol-video.md):
//
//   video:
//     backend: sim
//     sim: {scene: testbed.yaml, seed: 1}   # both optional
//
//  - sim.scene: a scene file (common/sim/scene_yaml.h, docs/site.md); default the thesis's
//    testbed (site::DefaultTestbedScene()).
//  - sim.seed: the sensor noise seed, overriding the scene's sensor.seed.
//  - lab.calibration, when set, gives the cameras (P and image size): the simulated site is
//    seen through the calibration every other process uses, so what the object server
//    computes from the lab's calibration is consistent with the pixels. The renderer casts
//    rays through P alone: a lens in the calibration (K, dist) is not simulated.
//
// Every grab renders the same scene with the same seed, so two grabs at one pose give
// identical images (the site does not change).
//
// The platform pose: the cameras' P are the calibrated ones, valid at the platform's zero
// pose. With a platform model (the calibration's `platform` map) a capture at joint angles q
// renders each camera with geometry::CameraAtPose(P, model, q), so panning the platform pans
// the view exactly as the model predicts; q takes the pose's angles in the model's joint
// order (pan, tilt, roll), joints beyond the pose's three at zero. Without a model the pose
// is stamped on the result but cannot move the cameras: the first non-zero pose logs one
// warning saying so.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "common/config/process_options.h"
#include "common/geometry/platform.h"
#include "common/sim/scene.h"
#include "video_server/capture_backend.h"
#include "video_server/capture_registry.h"

namespace igms::video {

// A backend rendering `scene` (cameras included, at the platform's zero pose) on every
// capture, moved by `platform` as above when there is one.
std::unique_ptr<CaptureBackend> MakeSimCapture(
    site::Scene scene, std::string origin,
    std::optional<geometry::PlatformModel> platform = std::nullopt);

// The scene's cameras moved to the platform pose: each P becomes CameraAtPose(P, platform, q)
// (image size and lens kept). The scene unchanged when `platform` is empty.
site::StereoCameras CamerasAtPose(const site::StereoCameras& cameras,
                                  const std::optional<geometry::PlatformModel>& platform,
                                  const PoseStamp& pose);

struct SimSceneChoice {
  std::optional<site::Scene> scene;
  std::optional<geometry::PlatformModel> platform;  // the calibration's, when it has one
  std::string origin;                               // "default testbed" or the scene file's path
  std::string error;  // set when scene is empty; names the key at fault
};

// The sim backend's keys (processes.NAME.sim.*), registered with the backend for VideoKeys.
struct SimCaptureOptions {
  std::string scene_file;  // absolute; empty: the thesis testbed
  int seed = -1;           // the sensor noise seed; negative: the scene's
};
config::Keys SimCaptureKeys(SimCaptureOptions* options);

// The scene the lab configuration describes for process `process` (see above): the scene
// file or the default testbed, the calibration's cameras, the seed override.
SimSceneChoice ConfiguredSimScene(const config::ProcessOptions& process);

// The backend `backend: sim` builds: ConfiguredSimScene rendered by MakeSimCapture.
BackendChoice MakeConfiguredSimCapture(const config::ProcessOptions& process);

// Registers MakeConfiguredSimCapture as the capture backend `sim`.
void RegisterSimCapture();

}  // namespace igms::video
