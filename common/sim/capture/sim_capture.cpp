#include "common/sim/capture/sim_capture.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <array>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "common/calibration/calibration_file.h"
#include "common/sim/renderer.h"
#include "common/sim/scene_yaml.h"
#include "common/sim/testbed.h"

namespace igms::video {

namespace {

geometry::ProjectiveCamera MoveCamera(const geometry::ProjectiveCamera& camera,
                                      const geometry::PlatformModel& platform,
                                      const std::vector<double>& q) {
  const geometry::Matrix34 P = geometry::CameraAtPose(camera.P(), platform, q);
  return camera.lens() ? geometry::ProjectiveCamera(P, camera.image_size(), *camera.lens())
                       : geometry::ProjectiveCamera(P, camera.image_size());
}

}  // namespace

site::StereoCameras CamerasAtPose(const site::StereoCameras& cameras,
                                  const std::optional<geometry::PlatformModel>& platform,
                                  const PoseStamp& pose) {
  if (!platform) return cameras;
  std::vector<double> q(platform->joints.size(), 0.0);
  for (size_t i = 0; i < q.size() && i < pose.joints_rad.size(); ++i) q[i] = pose.joints_rad[i];
  return {MoveCamera(cameras.left, *platform, q), MoveCamera(cameras.right, *platform, q)};
}

std::unique_ptr<CaptureBackend> MakeSimCapture(site::Scene scene, std::string origin,
                                               std::optional<geometry::PlatformModel> platform) {
  const auto size = scene.cameras.left.image_size();
  std::string description =
      fmt::format("sim: {} ({} objects, {}x{}, seed {}, {})", origin, scene.objects.size(),
                  size.width, size.height, scene.sensor.seed,
                  platform ? fmt::format("{}-joint platform model", platform->joints.size())
                           : std::string("no platform model"));
  // The renderer keeps no state; the scene is captured by value and only its cameras move.
  auto warned = std::make_shared<bool>(false);
  // The same pose gives the same pixels (the sensor's noise is seeded), so the last pair is
  // reused while the pose stands still: live video is not held to the ray caster's rate.
  struct Last {
    std::mutex mutex;
    std::optional<std::array<double, 3>> joints;
    cv::Mat left, right;
  };
  auto last = std::make_shared<Last>();
  return std::make_unique<RenderCapture>(
      std::move(description), [scene = std::move(scene), platform = std::move(platform), warned,
                               last](const PoseStamp& pose) {
        if (!platform && !pose.IsZero() && !*warned) {
          *warned = true;
          spdlog::warn(
              "sim: the calibration has no platform model, so the platform pose is stamped "
              "on each grab but the cameras stay at the zero pose");
        }
        // Without a platform model the cameras never move: every pose is the same view.
        const std::array<double, 3> key =
            platform ? pose.joints_rad : std::array<double, 3>{0.0, 0.0, 0.0};
        {
          std::lock_guard lock(last->mutex);
          if (last->joints == key) {
            StereoImages images;
            images.left = last->left.clone();
            images.right = last->right.clone();
            return CaptureResult::Ok(std::move(images));
          }
        }
        site::Scene posed = scene;
        posed.cameras = CamerasAtPose(scene.cameras, platform, pose);
        site::StereoImages pair = site::RenderStereo(posed);
        {
          std::lock_guard lock(last->mutex);
          last->joints = key;
          last->left = pair.left.clone();
          last->right = pair.right.clone();
        }
        StereoImages images;
        images.left = std::move(pair.left);
        images.right = std::move(pair.right);
        return CaptureResult::Ok(std::move(images));
      });
}

config::Keys SimCaptureKeys(SimCaptureOptions* options) {
  config::Keys keys;
  keys.BindPath("sim.scene", &options->scene_file,
                "sim: the site's scene file (default: the thesis testbed)");
  keys.Bind("sim.seed", &options->seed, "sim: the sensor noise seed (default: the scene's)");
  return keys;
}

SimSceneChoice ConfiguredSimScene(const config::ProcessOptions& process) {
  SimSceneChoice choice;
  SimCaptureOptions options;
  SimCaptureKeys(&options).Read(process);
  const std::string scene_key = process.Key("sim.scene");
  if (options.scene_file.empty()) {
    choice.scene = site::DefaultTestbedScene();
    choice.origin = "default testbed";
  } else {
    const std::string& path = options.scene_file;
    site::SceneLoad load = site::LoadSceneFile(path);
    if (!load.scene) {
      choice.error = scene_key + ": " + load.error;
      return choice;
    }
    choice.scene = std::move(load.scene);
    choice.origin = path;
  }
  if (!process.lab.calibration.empty()) {
    const auto calibration = calibration::LoadCalibration(process.lab.calibration);
    if (!calibration.ok()) {
      choice.scene.reset();
      choice.error = "lab.calibration: " + calibration.error();
      return choice;
    }
    choice.scene->cameras.left = calibration->left.Camera();
    choice.scene->cameras.right = calibration->right.Camera();
    choice.platform = calibration->platform;
  }
  if (options.seed >= 0) choice.scene->sensor.seed = static_cast<uint64_t>(options.seed);
  return choice;
}

BackendChoice MakeConfiguredSimCapture(const config::ProcessOptions& process) {
  BackendChoice choice;
  SimSceneChoice sim = ConfiguredSimScene(process);
  if (sim.scene) {
    choice.backend = MakeSimCapture(std::move(*sim.scene), sim.origin, std::move(sim.platform));
  } else {
    choice.error = sim.error;
  }
  return choice;
}

void RegisterSimCapture() {
  SimCaptureOptions declared;
  RegisterCaptureBackend("sim", MakeConfiguredSimCapture, SimCaptureKeys(&declared));
}

}  // namespace igms::video
