// Where the simulated ranger is and what it sees: the simulated site (common/site) ranged
// from the sensor's mount, which moves with the camera platform.
//
// The mount comes from the calibration file's `ranger` map (common/calibration/
// calibration_file.h): the sensor's origin and axis in the platform's end frame. With the
// calibration's `platform` model (common/geometry/platform.h) the beam at joint angles q is
//     origin(q) = world_from_end(q) origin_end,   axis(q) = R_world_from_end(q) axis_end,
// that is the zero-pose beam moved by WorldMotion(q), the same motion the cameras make.
// Without a platform model the end frame is the world frame and the beam never moves.
// Without a `ranger` map the sensor sits midway between the two camera centres, looking
// along the mean of their optical axes at the zero pose (the thesis mounted it between the
// cameras, Cooke, "Interactive Graphical Model Building using Virtual Reality", section
// 2.1.5).
//
// The range is the nearest surface inside the 12-degree beam cone (common/site/range.h,
// RangeInCone: the distance along the ray that meets it, as an echo's time of flight
// says), in the site's units (inches).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/calibration/calibration_file.h"
#include "common/geometry/platform.h"
#include "common/geometry/ranger_beam.h"
#include "common/site/scene.h"
#include "igms/devices.pb.h"

namespace igms::devices {

using RangerBeam = geometry::RangerBeam;  // common/geometry/ranger_beam.h

struct RangerMount {
  calibration::RangerCalibration sensor;  // in the end frame (the world without a platform)
  std::optional<geometry::PlatformModel> platform;

  // The mount of a calibration, as above.
  static RangerMount FromCalibration(const calibration::StereoCalibration& calibration);
  // The beam at joint angles q in radians, in the platform model's joint order
  // (geometry::RangerBeamAt: missing angles count as zero, extra ones are ignored; without
  // a platform model q is ignored).
  RangerBeam BeamAt(std::span<const double> q) const;
  // Joint angles of a platform reading: its encoder ticks (yaw, pitch, roll) through the
  // model's tick scales, as many as the model has joints. Empty without a platform model.
  std::vector<double> AnglesOf(const PlatformState& reading) const;
};

// The nearest surface inside a beam of `beam_width_deg` (full angle) from `beam`, without
// noise; nullopt when the cone meets nothing.
std::optional<double> SiteRange(const site::Scene& scene, const RangerBeam& beam,
                                double beam_width_deg);

// What the simulated ranger ranges: a scene file (common/site/scene_yaml.h) or, when
// `scene_file` is empty, the thesis's default testbed (common/site/testbed.h); the mount
// from the calibration file `calibration_file`, or, when it is empty, from the scene's own
// cameras without a platform. nullopt with a message naming the file on failure.
struct RangerWorld {
  site::Scene scene;
  RangerMount mount;
};
std::optional<RangerWorld> LoadRangerWorld(const std::string& scene_file,
                                           const std::string& calibration_file, std::string* error);

}  // namespace igms::devices
