// Reading the stereo calibration file (BRIEF contract): YAML readable by cv::FileStorage with
// maps `left` and `right`, each holding `P` (3x4 !!opencv-matrix) and `image_size`
// ([width, height]). Other keys (K, dist, platform, ranger) are ignored here.
// A stop-gap until the shared calibration loader lands in common/geometry.
#pragma once

#include <optional>
#include <string>

#include "common/geometry/camera.h"

namespace igms::object {

struct StereoCalibration {
  geometry::ProjectiveCamera left, right;
};

struct CalibrationLoad {
  std::optional<StereoCalibration> calibration;
  std::string error;
};

CalibrationLoad LoadStereoCalibration(const std::string& path);
// Writes a file LoadStereoCalibration reads back (used by tests and the demo).
bool SaveStereoCalibration(const std::string& path, const StereoCalibration& calibration);

}  // namespace igms::object
