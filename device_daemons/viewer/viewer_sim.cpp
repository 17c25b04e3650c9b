#include "device_daemons/viewer/viewer_sim.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace igms::devices {

Result<std::vector<ViewerKeyframe>> ParseViewerPath(const std::string& text) {
  std::vector<ViewerKeyframe> path;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    ViewerKeyframe k;
    if (!(fields >> k.t_s)) {
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      return ErrorMessage{"path line " + std::to_string(number) + ": expected a time"};
    }
    boom::Pose& p = k.pose;
    if (!(fields >> p.x_m >> p.y_m >> p.z_m >> p.yaw_deg >> p.pitch_deg >> p.roll_deg)) {
      return ErrorMessage{"path line " + std::to_string(number) +
                          ": expected t x y z yaw pitch roll"};
    }
    int buttons = 0;
    if (fields >> buttons && (buttons < 0 || buttons > 3)) {
      return ErrorMessage{"path line " + std::to_string(number) + ": buttons must be 0..3"};
    }
    p.left = buttons & 2;
    p.right = buttons & 1;
    if (!std::isfinite(k.t_s) || (!path.empty() && k.t_s <= path.back().t_s) ||
        (path.empty() && k.t_s != 0)) {
      return ErrorMessage{"path line " + std::to_string(number) +
                          ": times must start at 0 and increase"};
    }
    path.push_back(k);
  }
  if (path.empty()) {
    return ErrorMessage{"path has no keyframes"};
  }
  return path;
}

boom::Pose PoseAt(const std::vector<ViewerKeyframe>& path, double t_s) {
  if (path.size() == 1) return path.front().pose;
  const double duration = path.back().t_s;
  t_s = std::fmod(std::max(0.0, t_s), duration);
  auto next = std::upper_bound(path.begin(), path.end(), t_s,
                               [](double t, const ViewerKeyframe& k) { return t < k.t_s; });
  if (next == path.end()) return path.back().pose;
  const ViewerKeyframe& a = *(next - 1);
  const ViewerKeyframe& b = *next;
  const double f = (t_s - a.t_s) / (b.t_s - a.t_s);
  const auto mix = [f](double u, double v) { return u + (v - u) * f; };
  boom::Pose p;
  p.x_m = mix(a.pose.x_m, b.pose.x_m);
  p.y_m = mix(a.pose.y_m, b.pose.y_m);
  p.z_m = mix(a.pose.z_m, b.pose.z_m);
  p.yaw_deg = mix(a.pose.yaw_deg, b.pose.yaw_deg);
  p.pitch_deg = mix(a.pose.pitch_deg, b.pose.pitch_deg);
  p.roll_deg = mix(a.pose.roll_deg, b.pose.roll_deg);
  p.left = a.pose.left;
  p.right = a.pose.right;
  return p;
}

namespace {

Eigen::Isometry3d SitePose(const boom::Pose& p, double units_per_metre) {
  return HeadPoseFromMetres({p.x_m, p.y_m, p.z_m}, {p.yaw_deg, p.pitch_deg, p.roll_deg},
                            units_per_metre);
}

PoseTrackerOptions TrackerOptions(const ViewerSimOptions& o) {
  PoseTrackerOptions t;
  t.site_from_power_up = SitePose(o.power_up, t.site_units_per_metre);
  t.position_step_m = boom::kPositionStepM;
  t.angle_step_deg = boom::kAngleStepDeg;
  return t;
}

}  // namespace

ViewerSim::ViewerSim(ViewerSimOptions options) : tracker_(TrackerOptions(options)) {}

void ViewerSim::SetSteady(const boom::Pose& pose) {
  steady_ = pose;
  path_.clear();
}

void ViewerSim::SetPath(std::vector<ViewerKeyframe> path) {
  path_ = std::move(path);
  path_start_ns_ = -1;
}

void ViewerSim::SetButtons(bool left, bool right) { buttons_ = std::make_pair(left, right); }

boom::Pose ViewerSim::HeadNow(int64_t now_ns) const {
  boom::Pose p = steady_;
  if (!path_.empty()) {
    p = PoseAt(path_,
               path_start_ns_ < 0 ? 0.0 : static_cast<double>(now_ns - path_start_ns_) * 1e-9);
  }
  if (buttons_) std::tie(p.left, p.right) = *buttons_;
  return p;
}

boom::Pose ViewerSim::PoseNow(int64_t now_ns) const {
  const boom::Pose head = HeadNow(now_ns);
  const TrackerReading r = tracker_.Read(SitePose(head, tracker_.options().site_units_per_metre));
  boom::Pose p = head;
  p.x_m = r.position_m.x();
  p.y_m = r.position_m.y();
  p.z_m = r.position_m.z();
  p.yaw_deg = r.ypr_deg[0];
  p.pitch_deg = r.ypr_deg[1];
  p.roll_deg = r.ypr_deg[2];
  return p;
}

std::string ViewerSim::Report(int64_t now_ns) {
  if (!path_.empty() && path_start_ns_ < 0) path_start_ns_ = now_ns;
  boom::Pose p = PoseNow(now_ns);
  p.counter = counter_++ & 0x0F;
  return boom::EncodeReport(p);
}

std::vector<std::string> ViewerSim::OnInput(std::string_view bytes, int64_t now_ns) {
  std::vector<std::string> out;
  for (char c : bytes) {
    if (c == boom::kPoll) {
      out.push_back(Report(now_ns));
    } else if (c == boom::kStream) {
      streaming_ = true;
      next_report_ns_ = now_ns;
    } else if (c == boom::kStop) {
      streaming_ = false;
    }
  }
  return out;
}

std::vector<std::string> ViewerSim::Poll(int64_t now_ns, int64_t* next_wake_ns) {
  std::vector<std::string> out;
  if (!streaming_) return out;
  const auto period = static_cast<int64_t>(1e9 / boom::kMaxRateHz);
  if (now_ns >= next_report_ns_) {
    out.push_back(Report(now_ns));
    next_report_ns_ += period;
    if (next_report_ns_ < now_ns) next_report_ns_ = now_ns + period;
  }
  *next_wake_ns = std::min(*next_wake_ns, next_report_ns_);
  return out;
}

}  // namespace igms::devices
