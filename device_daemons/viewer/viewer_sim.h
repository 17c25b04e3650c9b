// A simulated BOOM viewer speaking boom_protocol.h: a pose tracker of the site
// (pose_tracker.h) driven by a steady head pose, or head motion scripted by a
// path (keyframes interpolated linearly, looping), plus the two handle buttons.
//
// The steady pose and the path's keyframes are the head's pose in the site: a position in
// metres and yaw, pitch, roll in degrees, both along the site's axes. Each report is what
// the tracker reads for it: the pose relative to the power-up pose (ViewerSimOptions;
// default the site's origin, level, so a pose is reported as given), at the BOOM's
// resolution and range.
//
// Path file: one keyframe a line, "t_s x_m y_m z_m yaw_deg pitch_deg roll_deg [buttons]",
// times increasing from 0; '#' starts a comment. buttons is 0..3 as in table 2.1 (left is
// the first digit).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "device_daemons/serial/pty_host.h"
#include "device_daemons/viewer/boom_protocol.h"
#include "device_daemons/viewer/pose_tracker.h"

namespace igms::devices {

struct ViewerKeyframe {
  double t_s = 0;
  boom::Pose pose;
};

// Parses a path file's text. An error with a message naming the line.
Result<std::vector<ViewerKeyframe>> ParseViewerPath(const std::string& text);
// The pose at time t_s (looping over the path's duration).
boom::Pose PoseAt(const std::vector<ViewerKeyframe>& path, double t_s);

struct ViewerSimOptions {
  boom::Pose power_up;  // the head's pose in the site at power-up (metres, degrees)
};

class ViewerSim : public SimulatedDevice {
 public:
  explicit ViewerSim(ViewerSimOptions options = {});
  std::vector<std::string> OnInput(std::string_view bytes, int64_t now_ns) override;
  std::vector<std::string> Poll(int64_t now_ns, int64_t* next_wake_ns) override;

  // The head's pose in the site (metres, degrees); buttons as set by SetButtons.
  void SetSteady(const boom::Pose& pose);
  void SetPath(std::vector<ViewerKeyframe> path);  // starts at the next report
  void SetButtons(bool left, bool right);
  // The head's pose in the site now, and what the tracker reports for it.
  boom::Pose HeadNow(int64_t now_ns) const;
  boom::Pose PoseNow(int64_t now_ns) const;

 private:
  std::string Report(int64_t now_ns);

  PoseTracker tracker_;
  boom::Pose steady_;
  std::vector<ViewerKeyframe> path_;
  int64_t path_start_ns_ = -1;
  std::optional<std::pair<bool, bool>> buttons_;
  uint8_t counter_ = 0;
  bool streaming_ = false;
  int64_t next_report_ns_ = 0;
};

}  // namespace igms::devices
