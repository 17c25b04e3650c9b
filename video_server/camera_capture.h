// The `camera` capture backend: live cameras through OpenCV's cv::VideoCapture.
//
// Two devices (left and right), or one side-by-side stereo device whose frames hold the left
// image in their left half and the right image in their right half. A device is named by its
// index ("0"), a path ("/dev/video2"), or anything else cv::VideoCapture opens (a video file
// or stream URL, which is how the tests drive this backend without a camera).
//
// Each device has a reader thread that opens it, reads frames as they come (keeping only the
// newest, so a grab is never a stale buffered frame) and stamps each with the wall-clock time
// it was read. A device that cannot be opened, or that stops delivering (read fails, end of
// a file), is released and reopened every retry_interval, with a warning in the log.
//
// Capture waits for a frame read after the call began from every device, at most
// frame_timeout; otherwise it returns an error naming the device and what is wrong ("cannot
// open", "no frame for 1000 ms"), never blocking longer. Construction never fails and never
// blocks: devices appear whenever they can be opened.
#pragma once

#include <chrono>
#include <memory>
#include <string>

#include "video_server/capture_backend.h"

namespace igms::video {

struct CameraCaptureOptions {
  std::string left;
  // Empty for a side-by-side device.
  std::string right;
  bool side_by_side = false;
  // Requested frame size of each device (0: the device's default). For a side-by-side
  // device this is the size of the whole frame.
  int width = 0;
  int height = 0;
  // Deliver 3-channel BGR instead of 8-bit grey.
  bool colour = false;
  // Readers of sources that are not paced by hardware (video files) read at most this many
  // frames per second; 0 reads as fast as the source delivers.
  double pace_fps = 0.0;
  std::chrono::milliseconds frame_timeout{1000};
  std::chrono::milliseconds retry_interval{1000};

  bool Check(std::string* error) const;
};

// Starts the reader threads. Returns nullptr only when options.Check() fails (error set).
std::unique_ptr<CaptureBackend> MakeCameraCapture(const CameraCaptureOptions& options,
                                                  std::string* error);

}  // namespace igms::video
