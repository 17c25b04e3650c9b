// Calibration of the camera platform's Denavit-Hartenberg model (Cooke, section 3.4) by
// nonlinear least squares (Levenberg-Marquardt) from world/image correspondences collected
// at several platform orientations, with each camera's P at the zero pose known (from DLT or
// a chessboard).
//
// Model: common/geometry/platform.h. A camera's pixel at joint angles q is
// P0 world_motion(q)^-1 X. Only the joint axes (as world lines at the zero pose) and the tick
// scales are observable, so the estimated parameters are a minimal set: the base pose
// (6: rotation vector and translation of world_from_base), joint 1's a and alpha, and every
// middle joint's theta_offset, d, a and alpha; joint 1's theta_offset and d and the last
// joint's four parameters keep their initial values (they shift along or rotate about an
// axis without changing any image). With `estimate_scales` the tick scales are estimated
// too. This needs at least two joints.
//
// Residuals are pixel distances in ideal pixels; each observation contributes its u and v.
// Convergence: the cost changes by less than 1e-12 of itself, or max_iterations.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/geometry/camera.h"
#include "common/geometry/platform.h"

namespace igms::calibration {

struct PlatformObservation {
  int camera = 0;             // 0 left, 1 right
  std::vector<double> ticks;  // encoder ticks, one per joint
  Eigen::Vector3d world = Eigen::Vector3d::Zero();
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // ideal (undistorted) pixel
};

struct PlatformCalibrationOptions {
  int max_iterations = 100;
  bool estimate_scales = false;
  bool Check(std::string* error) const;
};

struct PlatformCalibrationResult {
  geometry::PlatformModel model;
  double initial_rms = 0;  // pixels, with the initial model
  double rms = 0;          // pixels, after calibration
  double max = 0;
  std::vector<double> residuals;  // pixel distance per observation
  int iterations = 0;
  int parameters = 0;
};

using PlatformProgress = std::function<void(int iteration, double rms)>;

// Fails (an ErrorMessage saying why) when the options or initial model are bad, fewer than
// two joints, an observation names a bad camera, has the wrong tick count or a non-finite
// value, there are fewer residuals than parameters, or the problem is singular (e.g. all
// observations at one pose).
Result<PlatformCalibrationResult> CalibratePlatform(
    const geometry::Matrix34& left_P0, const geometry::Matrix34& right_P0,
    const geometry::PlatformModel& initial, std::span<const PlatformObservation> observations,
    const PlatformCalibrationOptions& options = {}, const PlatformProgress& progress = {});

// Pixel residual per observation of a model.
std::vector<double> PlatformResiduals(const geometry::Matrix34& left_P0,
                                      const geometry::Matrix34& right_P0,
                                      const geometry::PlatformModel& model,
                                      std::span<const PlatformObservation> observations);

// Reads "camera t1 t2 ... tn x y z u v" lines (camera "left", "right", 0 or 1; n = joints;
// whitespace or commas; '#' comments). An ErrorMessage "line N: ..." on a malformed line.
Result<std::vector<PlatformObservation>> ParsePlatformObservations(const std::string& text,
                                                                   int joints);

}  // namespace igms::calibration
