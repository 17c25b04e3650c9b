// What the window draws for a session's view: the session's state (control/app's
// SessionView) plus what only the window knows (the video pair and its pose, the overlay
// settings, whether the video server is lost), turned into the renderer's DrawList.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "common/calibration/calibration_file.h"
#include "control/app/session_view.h"
#include "control/render/draw_list.h"

namespace igms::control {

// A stereo pair of the live video (VideoService.Live) with the pose it was taken at.
struct StereoFrame {
  cv::Mat left, right;         // 8-bit grey or BGR
  uint64_t sequence = 0;       // the server's live sequence; 0: no frame yet
  std::vector<double> joints;  // radians, the platform's pose at capture
  int64_t capture_unix_ns = 0;
};

struct ViewExtras {
  StereoFrame frame;
  bool video_lost = false;  // the video server is not answering: the frame is frozen
  int key_level = 0;
  Eigen::Vector2i video_offset = Eigen::Vector2i::Zero();
  bool show_help = false;
  std::string stereo;  // the stereo mode's name, for the heads-up line
  // Boxes' texture patches decoded once, by model id (null: decoded on every call).
  std::map<uint64_t, cv::Mat>* textures = nullptr;
};

// The keys' help (the window's key map), one line each.
std::vector<std::string> KeyHelp();

// The draw list: each eye's camera at the frame's pose (the frozen grab's while frozen),
// the models present (removed ones left out), wireframe or solid as the session says, the
// pointer and marks while model building, and the heads-up text: mode and prompt, the last
// model with its sigmas or the last failure's detail, peers that are down, the newest
// notices.
render::DrawList ViewFromSession(const SessionView& view,
                                 const calibration::StereoCalibration& calibration,
                                 const ViewExtras& extras);

// One session model as the renderer draws it; a box's texture patch (decoded from its PNG,
// or from `textures` by the model's id) where the model knows the camera of its grab.
render::DrawModel DrawModelOf(const SessionModel& model,
                              std::map<uint64_t, cv::Mat>* textures = nullptr);

}  // namespace igms::control
