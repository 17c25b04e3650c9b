#include "device_daemons/ranger/ranger_site.h"

#include <algorithm>
#include <cmath>

#include "common/site/range.h"
#include "common/site/scene_yaml.h"
#include "common/site/testbed.h"

namespace igms::devices {

namespace {

calibration::RangerCalibration BetweenTheCameras(const geometry::ProjectiveCamera& left,
                                                 const geometry::ProjectiveCamera& right) {
  calibration::RangerCalibration r;
  r.origin = 0.5 * (left.Center() + right.Center());
  r.axis = (left.ViewDirection() + right.ViewDirection()).normalized();
  return r;
}

}  // namespace

RangerMount RangerMount::FromCalibration(const calibration::StereoCalibration& c) {
  RangerMount mount;
  mount.platform = c.platform;
  if (c.ranger) {
    mount.sensor = *c.ranger;
  } else {
    // The default is placed in the world at the zero pose; stored in the end frame.
    mount.sensor = BetweenTheCameras(c.left.Camera(), c.right.Camera());
    if (mount.platform) {
      const std::vector<double> zero(mount.platform->joints.size(), 0.0);
      const Eigen::Isometry3d end_from_world =
          geometry::WorldFromEnd(*mount.platform, zero).inverse();
      mount.sensor.origin = end_from_world * mount.sensor.origin;
      mount.sensor.axis = end_from_world.linear() * mount.sensor.axis;
    }
  }
  mount.sensor.axis.normalize();
  return mount;
}

RangerBeam RangerMount::BeamAt(std::span<const double> q) const {
  return geometry::RangerBeamAt(sensor.origin, sensor.axis, platform, q);
}

std::vector<double> RangerMount::AnglesOf(const PlatformState& reading) const {
  if (!platform) return {};
  const double ticks[3] = {static_cast<double>(reading.yaw_ticks()),
                           static_cast<double>(reading.pitch_ticks()),
                           static_cast<double>(reading.roll_ticks())};
  std::vector<double> q(platform->joints.size(), 0.0);
  for (size_t i = 0; i < q.size() && i < 3; ++i)
    q[i] = ticks[i] * platform->joints[i].radians_per_tick;
  return q;
}

std::optional<double> SiteRange(const site::Scene& scene, const RangerBeam& beam,
                                double beam_width_deg) {
  return site::RangeInCone(scene, beam.origin, beam.axis, beam_width_deg / 2 * M_PI / 180.0);
}

std::optional<RangerWorld> LoadRangerWorld(const std::string& scene_file,
                                           const std::string& calibration_file,
                                           std::string* error) {
  RangerWorld world;
  if (scene_file.empty()) {
    world.scene = site::DefaultTestbedScene();
  } else {
    site::SceneLoad load = site::LoadSceneFile(scene_file);
    if (!load.scene) {
      *error = "ranger scene " + scene_file + ": " + load.error;
      return std::nullopt;
    }
    world.scene = std::move(*load.scene);
  }
  if (calibration_file.empty()) {
    calibration::StereoCalibration c;
    c.left.P = world.scene.cameras.left.P();
    c.right.P = world.scene.cameras.right.P();
    world.mount = RangerMount::FromCalibration(c);
    return world;
  }
  auto calibration = calibration::LoadCalibration(calibration_file, error);
  if (!calibration) {
    *error = "ranger calibration: " + *error;
    return std::nullopt;
  }
  world.mount = RangerMount::FromCalibration(*calibration);
  return world;
}

}  // namespace igms::devices
