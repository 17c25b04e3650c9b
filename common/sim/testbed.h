// The thesis's testbed (Cooke, section 4.1) as a scene, and a generator of random testbed
// scenes for accuracy benchmarks.
//
// Cameras: the thesis's calibration matrices (equations 4.1 and 4.2) for 512 x 480 images,
// from common/calibration/thesis_calibration.h.
// They put the camera centres about 3.7 in above the plane z = 0 near (20.9, 3.1) and
// (16.9, 4.0), looking along -y; so the table top is z = 0 and objects stand at y between
// about -33 and -81 (3 to 7 ft from the cameras).
#pragma once

#include <cstdint>
#include <string>

#include "common/sim/scene.h"

namespace igms::site {

geometry::Matrix34 ThesisLeftP();
geometry::Matrix34 ThesisRightP();
StereoCameras ThesisCameras();  // image size 512 x 480

// Overhead room lights plus a fill light from the cameras' side, as a lab would have.
Lighting DefaultLighting();

// The default scene: the table, upright cylinders of 3 to 12 in (radius 0.5 and 0.25), a
// lying cylinder and two blocks, 3 to 7 ft from the cameras, each wholly inside both images.
Scene DefaultTestbedScene();

struct RandomSceneOptions {
  int upright_cylinders = 2;
  int lying_cylinders = 1;
  int boxes = 1;
  double min_distance = 36.0;  // from the left camera centre, along the table (inches)
  double max_distance = 84.0;
  // Gap kept between objects' image rectangles (pixels) in both images, so one object's
  // marked region never holds another (the thesis assumes no occlusion, section 3.6).
  double image_gap = 28.0;
  int max_attempts = 2000;
  // This share of the blocks is turned about the vertical by up to box_max_yaw_deg either
  // way (drawn apart from the rest, so the cylinders of a seed stay where they were).
  double turned_box_share = 0.5;
  double box_max_yaw_deg = 40.0;
};

// A random testbed scene with the thesis's object sizes: cylinders 3-12 in high with radius
// 0.5 or 0.25 in (lying ones 3-8 in long, axis within 60 degrees of the image's horizontal
// so that they look longer than wide), blocks 1-4 in on a side, half of them turned. Every object
// is wholly inside both images with a margin. Deterministic for a seed; sensor.seed = seed.
Scene RandomTestbedScene(uint64_t seed, const RandomSceneOptions& options = {});

// Pixel bounding rectangle of a solid in one image (from its outline points); false when
// any part is behind the camera.
bool ImageBounds(const Shape& shape, const geometry::ProjectiveCamera& camera, double& u0,
                 double& v0, double& u1, double& v1);

}  // namespace igms::site
