#include "video_server/sim_capture.h"

#include <fmt/format.h>

#include "common/calibration/calibration_file.h"
#include "common/site/renderer.h"
#include "common/site/scene_yaml.h"
#include "common/site/testbed.h"

namespace igms::video {

std::unique_ptr<CaptureBackend> MakeSimCapture(site::Scene scene, std::string origin) {
  const auto size = scene.cameras.left.image_size();
  std::string description =
      fmt::format("sim: {} ({} objects, {}x{}, seed {})", origin, scene.objects.size(), size.width,
                  size.height, scene.sensor.seed);
  // The renderer is deterministic and keeps no state, so the scene is captured by value.
  return std::make_unique<RenderCapture>(std::move(description),
                                         [scene = std::move(scene)](const PoseStamp&) {
                                           site::StereoImages pair = site::RenderStereo(scene);
                                           StereoImages images;
                                           images.left = std::move(pair.left);
                                           images.right = std::move(pair.right);
                                           return CaptureResult::Ok(std::move(images));
                                         });
}

SimSceneChoice ConfiguredSimScene(const config::ProcessOptions& process) {
  SimSceneChoice choice;
  const std::string scene_key = process.Key("sim.scene");
  const std::string scene_file = process.Get<std::string>("sim.scene", "");
  if (scene_file.empty()) {
    choice.scene = site::DefaultTestbedScene();
    choice.origin = "default testbed";
  } else {
    const std::string path = process.config.ResolvePath(scene_file);
    site::SceneLoad load = site::LoadSceneFile(path);
    if (!load.scene) {
      choice.error = scene_key + ": " + load.error;
      return choice;
    }
    choice.scene = std::move(load.scene);
    choice.origin = path;
  }
  const std::string calibration_file = process.config.Get<std::string>("lab.calibration", "");
  if (!calibration_file.empty()) {
    std::string error;
    const auto calibration =
        calibration::LoadCalibration(process.config.ResolvePath(calibration_file), &error);
    if (!calibration) {
      choice.scene.reset();
      choice.error = "lab.calibration: " + error;
      return choice;
    }
    choice.scene->cameras.left = calibration->left.Camera();
    choice.scene->cameras.right = calibration->right.Camera();
  }
  const int seed = process.Get<int>("sim.seed", -1);
  if (seed >= 0) choice.scene->sensor.seed = static_cast<uint64_t>(seed);
  return choice;
}

}  // namespace igms::video
