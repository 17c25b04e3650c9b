// The scene file: YAML, every key optional except `objects` entries' type and dimensions.
// Full description with an example: docs/site.md.
//
//   cameras:            # default: the thesis's matrices (equations 4.1, 4.2), 512 x 480
//     image_size: [512, 480]
//     left:  [p11, p12, p13, p14, p21, ..., p34]   # 3x4 P, row-major, world -> pixels
//     right: [...]
//   sensor:   {noise_sigma: 2, blur_sigma: 0.7, seed: 1}
//   lighting: {ambient: 0.45, lights: [{direction: [x, y, z], intensity: 0.45}]}
//   table:    {enabled: true, x_min: -3, x_max: 45, y_min: -96, y_max: -24, albedo: 0.12,
//              hole_albedo: 0.02, hole_pitch: 1, hole_radius: 0.125, hole_origin: [0, 0],
//              background: 0.03}
//   objects:
//     - {name: c1, type: cylinder, center: [x, y, z], axis: [0, 0, 1], radius: 0.5,
//        height: 6, albedo: 0.85}
//     - {name: b1, type: box, center: [x, y, z], size: [sx, sy, sz],
//        rpy_deg: [roll, pitch, yaw], albedo: 0.8}      # R = Rz(yaw) Ry(pitch) Rx(roll)
//     - {name: s1, type: sphere, center: [x, y, z], radius: 1}
//
// Lengths in the world's units (inches for the testbed). Missing sections take the
// defaults of DefaultTestbedScene() for cameras and lighting, and of the structs in scene.h.
#pragma once

#include <optional>
#include <string>

#include "common/sim/scene.h"

namespace igms::site {

struct SceneLoad {
  std::optional<Scene> scene;
  std::string error;  // set when scene is empty: what is wrong and where
};

SceneLoad ParseSceneYaml(const std::string& text);
SceneLoad LoadSceneFile(const std::string& path);
// A YAML document that ParseSceneYaml reads back into the same scene.
std::string SceneToYaml(const Scene& scene);

}  // namespace igms::site
