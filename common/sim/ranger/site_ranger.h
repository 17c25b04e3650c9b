// The simulated site as the world the ranger simulator ranges (device_daemons/ranger/
// ranger_site.h): igms-rangerd calls RegisterSiteRanger() so that `source: simulate` ranges
// the site, while the ranger's library never links the simulation.
//
// The world: a scene file (common/sim/scene_yaml.h) or, when `scene_file` is empty, the
// thesis's default testbed (common/sim/testbed.h); the mount from the calibration file
// `calibration_file`, or, when it is empty, from the scene's own cameras without a platform.
// The range is the nearest surface inside the beam cone (common/sim/range.h, RangeInCone).
#pragma once

#include <optional>
#include <string>

#include "common/sim/scene.h"
#include "device_daemons/ranger/ranger_site.h"

namespace igms::devices {

// The nearest surface of `scene` inside a beam of `beam_width_deg` (full angle) from `beam`,
// without noise; nullopt when the cone meets nothing.
std::optional<double> SiteRange(const site::Scene& scene, const RangerBeam& beam,
                                double beam_width_deg);

// The site world described above; an error naming the file on failure.
Result<RangerWorld> LoadSiteRangerWorld(const std::string& scene_file,
                                        const std::string& calibration_file);

// The thesis's testbed with the sensor between its cameras: LoadSiteRangerWorld("", "").
RangerWorld TestbedRangerWorld();

// Registers LoadSiteRangerWorld as the ranger simulator's world (RegisterRangerWorld).
void RegisterSiteRanger();

}  // namespace igms::devices
