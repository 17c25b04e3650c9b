// Operator marks generated from the ground truth, as the object server's issue models a
// human operator helped by the ultrasonic ranger (Cooke, sections 2.1.5, 3.8, 4.3):
//
//  - four 3D points, the corners of a rectangle facing the left camera (in a plane of
//    constant left-camera depth) that bounds the object's silhouette as the left camera
//    sees it, each side 0.2 to 1 in (uniform) outside the silhouette's bounding box;
//  - the plane's depth is the object's front-surface depth plus one error shared by all four
//    marks, normal with sigma 1 in, clipped at +/- 3 in;
//  - each corner then jittered within the plane by a normal error of sigma 0.1 in per axis.
//
// Only tests, benchmarks and the demo use this: the locator never sees the ground truth.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>

#include "common/sim/scene.h"

namespace igms::site {

struct MarkModel {
  double margin_min = 0.2;  // inches outside the silhouette, per side
  double margin_max = 1.0;
  double depth_sigma = 1.0;
  double depth_clip = 3.0;
  double lateral_sigma = 0.1;
};

using Marks = std::array<Eigen::Vector3d, 4>;

// The marks for one solid, or nullopt when it is not wholly in front of the left camera.
// Order: top-left, top-right, bottom-right, bottom-left as the left camera sees them.
std::optional<Marks> GenerateMarks(const Shape& shape, const geometry::ProjectiveCamera& left,
                                   uint64_t seed, const MarkModel& model = {});

// The depth (along the left camera's optical axis) of the solid's nearest outline point.
double FrontDepth(const Shape& shape, const geometry::ProjectiveCamera& camera);

}  // namespace igms::site
