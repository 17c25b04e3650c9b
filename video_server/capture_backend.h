// Where stereo pairs come from: one interface, backends chosen by name at run time
// (capture_registry.h).
//
//  - files:  a stereo pair of image files, or a numbered sequence of pairs (files_capture.h).
//  - camera: two cv::VideoCapture devices, or one side-by-side stereo device
//            (camera_capture.h).
//  - sim:    the simulated site's renderer, registered by the program that links the
//            simulation. Any function that renders a pair for a platform pose becomes a
//            backend through RenderCapture below, so the simulator needs only a few lines of
//            adapter (common/sim/capture/sim_capture.h).
//
// A backend is used from one thread at a time (the video server serialises Capture calls).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "video_server/stereo_frame.h"

namespace igms::video {

// The outcome of one capture: the pair, or an error saying what failed and what the backend
// does about it (e.g. "retrying every 1 s").
struct CaptureResult {
  std::optional<StereoImages> images;
  std::string error;

  bool ok() const { return images.has_value(); }
  static CaptureResult Ok(StereoImages images);
  static CaptureResult Error(std::string message);
};

class CaptureBackend {
 public:
  virtual ~CaptureBackend() = default;

  // Captures a pair now. `pose` is the platform pose the caller knows at this moment (zero
  // without a platform); a camera or file backend passes it through into the result, the
  // simulator renders the site at it. Never blocks longer than the backend's documented
  // timeout; a missing or silent device is an error result, never a hang or an exception.
  virtual CaptureResult Capture(const PoseStamp& pose) = 0;

  // One line for logs and the Ping answer, e.g. "files: left01.jpg / right01.jpg (13 pairs)".
  virtual std::string Describe() const = 0;
};

// A backend around a render function: the simulated site, or any other synthetic source. The
// function is called with the pose and returns the pair (its capture times are filled in
// with the time rendering started when the function leaves them zero), or an error.
using RenderFunction = std::function<CaptureResult(const PoseStamp& pose)>;

class RenderCapture : public CaptureBackend {
 public:
  RenderCapture(std::string description, RenderFunction render);
  CaptureResult Capture(const PoseStamp& pose) override;
  std::string Describe() const override { return description_; }

 private:
  std::string description_;
  RenderFunction render_;
};

}  // namespace igms::video
