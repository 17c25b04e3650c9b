// The stereo calibration file (see docs/calibration.md): YAML read and written with
// cv::FileStorage.
//
//   %YAML:1.0
//   ---
//   left:
//     P: !!opencv-matrix { rows: 3, cols: 4, dt: d, data: [...] }   # required, world -> ideal px
//     image_size: [512, 480]                                       # required, [width, height]
//     K: !!opencv-matrix { rows: 3, cols: 3, ... }                  # optional intrinsics
//     dist: !!opencv-matrix { rows: 1, cols: 5, ... }               # optional, OpenCV order;
//                                                                  # a plain [..] list also works
//   right: { same keys }
//   ranger:                     # optional: the ultrasonic sensor in the platform's end frame
//     origin: [x, y, z]
//     axis: [x, y, z]           # normalised on load
//   platform:                   # optional: Denavit-Hartenberg model (common/geometry/platform.h)
//     world_from_base: !!opencv-matrix { rows: 4, cols: 4, ... }
//     joints:
//       - { name: pan, theta_offset: 0., d: 6., a: 0., alpha: 1.5708, radians_per_tick: 6.43e-05 }
//
// Loading validates everything and names the offending key in its error ("left.P: expected
// a 3x4 matrix, got 3x3"): matrix shapes, finiteness, a finite camera centre (P's left 3x3
// block not singular), positive image sizes, K upper triangular and invertible, a supported
// number of distortion coefficients, `dist` only with `K`, a non-zero ranger axis, a valid
// platform. Unknown keys are ignored, so files may carry notes and extra figures.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/geometry/camera.h"
#include "common/geometry/platform.h"

namespace igms::calibration {

struct CameraCalibration {
  geometry::Matrix34 P = geometry::Matrix34::Zero();
  geometry::ImageSize image_size;
  std::optional<Eigen::Matrix3d> K;
  std::vector<double> dist;

  // The camera model: with a lens when K is present.
  geometry::ProjectiveCamera Camera() const;
};

struct RangerCalibration {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // unit length
};

struct StereoCalibration {
  CameraCalibration left;
  CameraCalibration right;
  std::optional<geometry::PlatformModel> platform;
  std::optional<RangerCalibration> ranger;
};

// Parses a calibration from YAML text; an error naming the key on failure.
Result<StereoCalibration> ParseCalibration(const std::string& yaml);
// Reads a calibration file; an error naming the file and the key on failure.
Result<StereoCalibration> LoadCalibration(const std::string& path);

// The YAML text of a calibration. The calibration must validate (std::invalid_argument
// otherwise: writing a file that cannot be read back is a programmer error).
std::string FormatCalibration(const StereoCalibration& calibration);
// Writes FormatCalibration to `path`; false with `error` when the file cannot be written.
bool SaveCalibration(const StereoCalibration& calibration, const std::string& path,
                     std::string* error = nullptr);

// The checks LoadCalibration applies, for calibrations built in code.
bool ValidateCalibration(const StereoCalibration& calibration, std::string* error = nullptr);

}  // namespace igms::calibration
