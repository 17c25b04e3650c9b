// Stereo calibration from chessboard image pairs with OpenCV, written as a calibration file.
//
// Pipeline:
//  1. Corners: cv::findChessboardCorners (adaptive threshold, normalised image; retried on the
//     image upscaled 2x when it fails, as OpenCV's stereo_calib sample does), then
//     cv::cornerSubPix (11x11 window). A pair is used only when both images show the board.
//  2. Each camera alone: cv::calibrateCamera with OpenCV's default 5-coefficient model
//     (k1 k2 p1 p2 k3), giving K, dist and that camera's RMS reprojection error.
//  3. The pair: cv::stereoCalibrate started from those intrinsics and refining everything
//     jointly (CALIB_USE_INTRINSIC_GUESS), giving R, t (right_from_left), E, F and the
//     stereo RMS reprojection error. (OpenCV's sample instead estimates all intrinsics inside
//     stereoCalibrate from a rough initCameraMatrix2D guess with an 8-coefficient rational
//     model and shared focal length; calibrating each camera first is what beats it.)
//  4. The average epipolar error exactly as the sample computes it: every corner undistorted
//     (cv::undistortPoints into pixel coordinates), the epipolar line of its match from F
//     (cv::computeCorrespondEpilines), and the distances of the left corner from its line
//     plus the right corner from its line, summed over all pairs and divided by the number of
//     corner pairs. `epipolar_error_per_image` is half of that: the mean distance in one image.
//
// Frames: the world is the left camera's frame at calibration (x right, y down, z forward),
// in the board's units (`square` per square). P_left = K_l [I | 0], P_right = K_r [R | t];
// both map to ideal pixels, the distortion being applied after them (camera.h's model).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/calibration/calibration_file.h"

namespace igms::calibration {

struct ChessboardOptions {
  int cols = 9;         // inner corners per row
  int rows = 6;         // inner corners per column
  double square = 1.0;  // square size, world units
  enum class Procedure {
    kJoint,         // per-camera calibrateCamera, then stereoCalibrate refining everything
    kFixed,         // per-camera calibrateCamera, then stereoCalibrate with intrinsics fixed
    kOpenCvSample,  // OpenCV's stereo_calib sample: initCameraMatrix2D, then stereoCalibrate
                    // with its flags (rational model, same focal length...): the baseline
  };
  Procedure procedure = Procedure::kJoint;

  bool Check(std::string* error) const;
};

struct ChessboardResult {
  StereoCalibration calibration;
  double left_rms = 0;  // pixels, each camera's own calibrateCamera (0 for kOpenCvSample)
  double right_rms = 0;
  double stereo_rms = 0;                // pixels, stereoCalibrate
  double epipolar_error = 0;            // pixels, as OpenCV's stereo_calib sample reports it
  double epipolar_error_per_image = 0;  // pixels, half of that
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // right_from_left
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  int pairs_used = 0;
  std::vector<std::string> skipped;  // "file: why" for every pair left out
};

// Progress messages ("corners 3/13: left03.jpg") for long runs; may be empty.
using Progress = std::function<void(const std::string&)>;

// Calibrates from left/right image files (paired by position). Fails (an ErrorMessage saying
// why) on bad options, unequal list lengths, an unreadable image, images of different sizes, or
// fewer than 3 usable pairs.
Result<ChessboardResult> CalibrateChessboard(const std::vector<std::string>& left,
                                             const std::vector<std::string>& right,
                                             const ChessboardOptions& options,
                                             const Progress& progress = {});

}  // namespace igms::calibration
