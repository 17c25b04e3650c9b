#include "device_daemons/ranger/ranger_site.h"

#include <algorithm>
#include <cmath>

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

namespace {

RangerWorldLoader& Loader() {
  static RangerWorldLoader loader;
  return loader;
}

}  // namespace

void RegisterRangerWorld(RangerWorldLoader loader) { Loader() = std::move(loader); }

Result<RangerWorld> LoadRangerWorld(const std::string& scene_file,
                                    const std::string& calibration_file) {
  if (!Loader()) {
    return ErrorMessage{
        "the ranger simulator has no world to range: this program was built without the "
        "simulated site (common/sim/ranger)"};
  }
  return Loader()(scene_file, calibration_file);
}

}  // namespace igms::devices
