// Random scenes that look like a site rather than the thesis's clean testbed, in levels, for
// the locator's accuracy benchmark and its seeded test (Cooke, "Interactive Graphical Model
// Building using Virtual Reality", sections 3.6-3.8 and 5: the thesis assumes no occlusion
// and white objects; a plant has neither).
//
//  - pipes: lying pipes in every horizontal direction (straight away from the cameras too),
//    resting on the table, raised on two blocks (as on a rack) or tilted with one end on a
//    block; objects kept apart in the image but for a pipe and its own supports.
//  - clutter: 4-8 objects (upright and lying cylinders, blocks) that may hide one another in
//    part or lie partly out of view; albedos from dark to white, textures, a table of varying
//    shade (low contrast included).
//  - far: 4-6 objects 6-8 ft away, apart in the image, noise sigma 6 grey levels.
// Every level: two lights with shadows, noise sigma 1-8 grey levels (6 for far), blur
// 0.5-1.2 px. Each level comes with the thesis's cameras or a 1920 x 1080 pair (HdCameras).
#pragma once

#include <cstdint>
#include <string>

#include "common/sim/scene.h"

namespace igms::site {

enum class SiteLevel { kPipes, kClutter, kFar };
const char* SiteLevelName(SiteLevel level);

// The thesis's cameras with 1920 x 1080 sensors: the same centres and horizontal field of
// view (pixels 3.75 times finer), cropped to 16:9 about the same optical centre.
StereoCameras HdCameras();

// Deterministic for (seed, level, hd); sensor.seed = seed.
Scene SiteScene(uint64_t seed, SiteLevel level, bool hd);

}  // namespace igms::site
