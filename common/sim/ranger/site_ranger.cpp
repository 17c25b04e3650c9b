#include "common/sim/ranger/site_ranger.h"

#include <cmath>
#include <memory>

#include "common/calibration/calibration_file.h"
#include "common/sim/range.h"
#include "common/sim/scene_yaml.h"
#include "common/sim/testbed.h"

namespace igms::devices {

std::optional<double> SiteRange(const site::Scene& scene, const RangerBeam& beam,
                                double beam_width_deg) {
  return site::RangeInCone(scene, beam.origin, beam.axis, beam_width_deg / 2 * M_PI / 180.0);
}

Result<RangerWorld> LoadSiteRangerWorld(const std::string& scene_file,
                                        const std::string& calibration_file) {
  // Shared, so that copies of the world (the simulator's options) share one scene.
  auto scene = std::make_shared<site::Scene>();
  if (scene_file.empty()) {
    *scene = site::DefaultTestbedScene();
  } else {
    site::SceneLoad load = site::LoadSceneFile(scene_file);
    if (!load.scene) return ErrorMessage{"ranger scene " + scene_file + ": " + load.error};
    *scene = std::move(*load.scene);
  }
  RangerWorld world;
  world.range = [scene = std::shared_ptr<const site::Scene>(scene)](const RangerBeam& beam,
                                                                    double beam_width_deg) {
    return SiteRange(*scene, beam, beam_width_deg);
  };
  if (calibration_file.empty()) {
    calibration::StereoCalibration c;
    c.left.P = scene->cameras.left.P();
    c.right.P = scene->cameras.right.P();
    world.mount = RangerMount::FromCalibration(c);
    return world;
  }
  auto calibration = calibration::LoadCalibration(calibration_file);
  if (!calibration.ok()) return ErrorMessage{"ranger calibration: " + calibration.error()};
  world.mount = RangerMount::FromCalibration(*calibration);
  return world;
}

RangerWorld TestbedRangerWorld() {
  // The built-in testbed needs no file, so this cannot fail.
  return *LoadSiteRangerWorld("", "");
}

void RegisterSiteRanger() { RegisterRangerWorld(LoadSiteRangerWorld); }

}  // namespace igms::devices
