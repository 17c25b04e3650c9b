// The `sim` capture backend: the simulated site (common/site) rendered as a stereo pair.
//
// Configuration (processes.NAME of the lab configuration, docs/protocol-video.md):
//
//   video:
//     backend: sim
//     sim: {scene: testbed.yaml, seed: 1}   # both optional
//
//  - sim.scene: a scene file (common/site/scene_yaml.h, docs/site.md); default the thesis's
//    testbed (site::DefaultTestbedScene()).
//  - sim.seed: the sensor noise seed, overriding the scene's sensor.seed.
//  - lab.calibration, when set, gives the cameras (P and image size): the simulated site is
//    seen through the calibration every other process uses, so what the object server
//    computes from the lab's calibration is consistent with the pixels. The renderer casts
//    rays through P alone: a lens in the calibration (K, dist) is not simulated.
//
// Every grab renders the same scene with the same seed, so two grabs give identical images
// (the site does not change). The pair is rendered at the calibrated pose; a platform pose
// passed to Capture is stamped on the result but does not move the cameras yet.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "common/config/process_options.h"
#include "common/site/scene.h"
#include "video_server/capture_backend.h"

namespace igms::video {

// A backend rendering `scene` (cameras included) on every capture.
std::unique_ptr<CaptureBackend> MakeSimCapture(site::Scene scene, std::string origin);

struct SimSceneChoice {
  std::optional<site::Scene> scene;
  std::string origin;  // "default testbed" or the scene file's path
  std::string error;   // set when scene is empty; names the key at fault
};

// The scene the lab configuration describes for process `process` (see above): the scene
// file or the default testbed, the calibration's cameras, the seed override.
SimSceneChoice ConfiguredSimScene(const config::ProcessOptions& process);

}  // namespace igms::video
