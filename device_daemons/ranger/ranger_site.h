// Where the simulated ranger is and what it sees: a world ranged from the sensor's mount,
// which moves with the camera platform. The world is the simulated site (common/sim), which
// this library does not link: a program registers its loader (common/sim/ranger/
// site_ranger.h; igms-rangerd does) and the simulator ranges whatever that loader returns.
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
// The range is the nearest surface inside the 12-degree beam cone (the distance along the
// ray that meets it, as an echo's time of flight says), in the site's units (inches).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/calibration/calibration_file.h"
#include "common/geometry/platform.h"
#include "common/geometry/ranger_beam.h"
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
using RangeFunction =
    std::function<std::optional<double>(const RangerBeam& beam, double beam_width_deg)>;

// What the simulated ranger ranges, and from where.
struct RangerWorld {
  RangeFunction range;  // empty: nothing echoes
  RangerMount mount;
};

// Makes the world from the daemon's scene file and calibration file (either may be empty
// for a default); an error naming the file on failure.
using RangerWorldLoader = std::function<Result<RangerWorld>(const std::string& scene_file,
                                                            const std::string& calibration_file)>;

// Sets the loader LoadRangerWorld uses. Call before starting a simulator, from one thread.
void RegisterRangerWorld(RangerWorldLoader loader);

// The registered loader's world; an error saying so when the program registered none (it was
// built without the simulated site).
Result<RangerWorld> LoadRangerWorld(const std::string& scene_file,
                                    const std::string& calibration_file);

}  // namespace igms::devices
