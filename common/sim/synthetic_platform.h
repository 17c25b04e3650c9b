// A synthetic camera platform with known parameters, for testing platform calibration and for
// its figures: the thesis-like stereo rig (512x480, cameras 4 inches apart 6 inches above the
// table, looking along +x) on a pan-tilt-roll head whose true DH parameters differ from the
// nominal ThesisPlatform by machining-sized errors, observing a 3D grid of known points at
// 27 orientations (pan +-15, tilt +-8, roll +-5 degrees) with Gaussian pixel noise.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "common/calibration/platform_calibration.h"

namespace igms::calibration {

struct PlatformScenario {
  geometry::Matrix34 P0[2];
  geometry::ImageSize size{512, 480};
  geometry::PlatformModel truth;
  geometry::PlatformModel nominal;  // the starting guess
  std::vector<PlatformObservation> observations;
};

PlatformScenario MakePlatformScenario(double pixel_noise, unsigned seed);

// A joint's axis at the zero pose as a world line (point on it, unit direction).
struct AxisLine {
  Eigen::Vector3d point;
  Eigen::Vector3d direction;
};
std::vector<AxisLine> JointAxes(const geometry::PlatformModel& model);

struct PlatformRecovery {
  double max_axis_angle_deg = 0;  // worst angle between a true and a recovered joint axis
  double max_axis_offset = 0;     // worst distance between them near the head, world units
  double max_scale_error = 0;     // worst relative tick-scale error
  double prediction_rms_px = 0;   // recovered vs true pixels at 200 random poses, noise-free
};

// How well `estimate` matches the scenario's truth.
PlatformRecovery CompareToTruth(const PlatformScenario& scenario,
                                const geometry::PlatformModel& estimate, unsigned seed);

}  // namespace igms::calibration
