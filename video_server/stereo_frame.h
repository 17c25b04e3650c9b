// A stereo pair as the video server captures it, with when and where it was taken.
//
// Images are 8-bit, one channel (grey, like the thesis's monochrome CCDs) or three (BGR, as
// OpenCV decodes colour). Both images of a pair have the same size and type. Pixel (0, 0) is
// the centre of the top-left pixel, u right, v down (common/geometry/camera.h).
#pragma once

#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

namespace igms::video {

// The camera platform's joint angles when the pair was taken, in radians, in the order of the
// calibration's platform model (pan, tilt, roll for a three-axis platform; the thesis's MOLLY
// used pan only). All zero, with from_platform false, when the lab has no platform: the
// cameras then sit at the pose their projection matrices were calibrated at.
struct PoseStamp {
  std::array<double, 3> joints_rad{0.0, 0.0, 0.0};
  // True when the angles were reported by a platform daemon, false for the zero pose.
  bool from_platform = false;
  // When the platform reported the angles, nanoseconds since the Unix epoch (0 if none).
  int64_t time_unix_ns = 0;

  bool IsZero() const { return joints_rad == std::array<double, 3>{0.0, 0.0, 0.0}; }
};

struct StereoImages {
  cv::Mat left;
  cv::Mat right;
  // When each image was captured (wall clock, ns since the Unix epoch). Cameras expose each
  // side at its own moment; files and the simulator stamp both with the same time.
  int64_t left_capture_unix_ns = 0;
  int64_t right_capture_unix_ns = 0;
  // The platform pose the pair was taken at.
  PoseStamp pose;
};

// Checks that both images are non-empty 8-bit 1- or 3-channel images of one size and type.
// Returns an empty string when they are, otherwise a sentence saying what is wrong.
std::string CheckStereoImages(const StereoImages& images);

}  // namespace igms::video
