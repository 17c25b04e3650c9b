#include "control/window/view_from_session.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "common/geometry/platform.h"

namespace igms::control {
namespace {

geometry::Matrix34 CameraAt(const geometry::Matrix34& P0,
                            const std::optional<geometry::PlatformModel>& platform,
                            const std::vector<double>& joints) {
  if (!platform) return P0;
  std::vector<double> q(platform->joints.size(), 0.0);
  std::copy_n(joints.begin(), std::min(joints.size(), q.size()), q.begin());
  return geometry::CameraAtPose(P0, *platform, q);
}

Eigen::Vector3d V(const object::Vec3& v) { return {v.x(), v.y(), v.z()}; }

std::string Prompt(const SessionView& view) {
  switch (view.mode) {
    case Mode::kStarting:
      return "waiting for the lab's peers";
    case Mode::kVerification:
      return "verification: look around; freeze (F) to model";
    case Mode::kFreezing:
      return "freezing: the platform settles";
    case Mode::kGrabbing:
      return "grabbing the stereo pair";
    case Mode::kModelBuilding:
      return fmt::format("model building: mark {} of 4 (space), range (R), unfreeze (U)",
                         std::min<size_t>(view.marks.size() + 1, 4));
    case Mode::kAwaitingType:
      return "identify the object: box (B) or cylinder (C)";
    case Mode::kLocating:
      return "locating the object...";
    case Mode::kStopped:
      return "the session has ended";
  }
  return "";
}

std::string ModelLine(const SessionModel& m) {
  if (m.type == object::OBJECT_TYPE_CYLINDER) {
    const auto& c = m.cylinder;
    return fmt::format(
        "model {}: cylinder r {:.2f}+-{:.2f} h {:.2f}+-{:.2f} at ({:.1f}, {:.1f}, {:.1f})", m.id,
        c.radius(), c.radius_sigma(), c.height(), c.height_sigma(), c.center().x(), c.center().y(),
        c.center().z());
  }
  const auto& b = m.box;
  const Eigen::Vector3d size = V(b.size()).norm() > 0 ? V(b.size()) : V(b.max()) - V(b.min());
  const Eigen::Vector3d sigma = V(b.max_sigma());
  return fmt::format("model {}: box {:.2f} x {:.2f} x {:.2f} (+-{:.2f} {:.2f} {:.2f}) yaw {:.1f}",
                     m.id, size.x(), size.y(), size.z(), sigma.x(), sigma.y(), sigma.z(),
                     b.yaw_deg());
}

render::HudLevel LevelOf(NoticeLevel level) {
  switch (level) {
    case NoticeLevel::kWarning:
      return render::HudLevel::kWarning;
    case NoticeLevel::kError:
      return render::HudLevel::kError;
    case NoticeLevel::kInfo:
      break;
  }
  return render::HudLevel::kInfo;
}

cv::Mat DecodePatch(const std::string& png) {
  const cv::Mat bytes(1, static_cast<int>(png.size()), CV_8UC1, const_cast<char*>(png.data()));
  try {
    return cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
    return {};
  }
}

}  // namespace

std::vector<std::string> KeyHelp() {
  return {
      "F freeze   U unfreeze   R range   Space mark   Backspace unmark   X remove marks",
      "B box   C cylinder   W wireframe/solid   Delete remove model   Z undo",
      "I/K up/down  J/L left/right  PgUp/PgDn farther/nearer (Shift: slow)  mouse: wheel depth,",
      "  left click mark, right click unmark   arrows: video offset   Tab: stereo mode",
      "P screenshot   H help   Esc quit",
  };
}

render::DrawModel DrawModelOf(const SessionModel& m, std::map<uint64_t, cv::Mat>* textures) {
  render::DrawModel d;
  if (m.type == object::OBJECT_TYPE_CYLINDER) {
    d.kind = render::DrawModel::Kind::kCylinder;
    d.center = V(m.cylinder.center());
    d.axis = V(m.cylinder.axis());
    if (d.axis.norm() < 1e-9) d.axis = Eigen::Vector3d::UnitZ();
    d.axis.normalize();
    d.radius = m.cylinder.radius();
    d.height = m.cylinder.height();
    d.color = {0.2f, 0.95f, 0.3f};
    return d;
  }
  d.kind = render::DrawModel::Kind::kBox;
  d.color = {0.25f, 0.8f, 1.0f};
  const Eigen::Vector3d size = V(m.box.size());
  if (size.minCoeff() > 0) {
    d.center = V(m.box.center());
    d.size = size;
    const double yaw = m.box.yaw_deg() * M_PI / 180.0;
    d.rotation = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  } else {  // the thesis's block: its world-axis-aligned extent
    d.center = 0.5 * (V(m.box.min()) + V(m.box.max()));
    d.size = (V(m.box.max()) - V(m.box.min())).cwiseAbs();
  }
  if (!m.box.texture_png().empty() && !m.left_P_at_grab.isZero()) {
    cv::Mat patch;
    if (textures) {
      auto [it, added] = textures->try_emplace(m.id);
      if (added) it->second = DecodePatch(m.box.texture_png());
      patch = it->second;
    } else {
      patch = DecodePatch(m.box.texture_png());
    }
    const cv::Rect rect(m.box.texture_u0(), m.box.texture_v0(),
                        m.box.texture_u1() - m.box.texture_u0() + 1,
                        m.box.texture_v1() - m.box.texture_v0() + 1);
    if (!patch.empty() && rect.width > 0 && rect.height > 0) {
      d.texture = patch;
      d.texture_rect = rect;
      d.texture_P = m.left_P_at_grab;
    }
  }
  return d;
}

render::DrawList ViewFromSession(const SessionView& view,
                                 const calibration::StereoCalibration& calibration,
                                 const ViewExtras& extras) {
  render::DrawList list;
  const calibration::CameraCalibration* cams[2] = {&calibration.left, &calibration.right};
  const cv::Mat* video[2] = {&extras.frame.left, &extras.frame.right};
  for (int eye = 0; eye < 2; ++eye) {
    render::EyeView& e = list.eyes[eye];
    e.size = cams[eye]->image_size;
    if (view.frozen) {
      e.P = eye == 0 ? view.frozen->left_P : view.frozen->right_P;
    } else {
      e.P = CameraAt(cams[eye]->P, calibration.platform, extras.frame.joints);
    }
    e.video = *video[eye];
    e.video_id = extras.frame.sequence;
    if (cams[eye]->K && !cams[eye]->dist.empty()) {
      e.lens = geometry::Lens{*cams[eye]->K, cams[eye]->dist};
    }
  }
  for (const SessionModel& m : view.models) {
    if (!m.removed) list.models.push_back(DrawModelOf(m, extras.textures));
  }
  list.wireframe = view.wireframe;
  if (view.frozen) {
    list.pointer = view.pointer;
    list.marks = view.marks;
  }
  list.key_level = extras.key_level;
  list.video_offset = extras.video_offset;

  std::string mode_line = fmt::format("IGMS  {}", ModeName(view.mode));
  if (!extras.stereo.empty()) mode_line += "   [" + extras.stereo + "]";
  mode_line += view.wireframe ? "   wireframe" : "   solid";
  list.hud.push_back({mode_line});
  list.hud.push_back({Prompt(view)});
  if (view.range > 0) list.hud.push_back({fmt::format("range {:.1f}", view.range)});
  if (view.mode == Mode::kAwaitingType && !view.failure_detail.empty()) {
    list.hud.push_back({"not found: " + view.failure_detail, render::HudLevel::kError});
  } else {
    for (auto it = view.models.rbegin(); it != view.models.rend(); ++it) {
      if (!it->removed) {
        list.hud.push_back({ModelLine(*it)});
        break;
      }
    }
  }
  std::string down;
  for (Peer peer : kAllPeers) {
    if (!view.peer_up[static_cast<int>(peer)]) {
      down += (down.empty() ? "" : ", ") + std::string(PeerName(peer));
    }
  }
  if (!down.empty() && view.mode != Mode::kStarting) {
    list.hud.push_back({"down: " + down, render::HudLevel::kWarning});
  }
  const size_t shown = std::min<size_t>(view.notices.size(), 3);
  for (size_t i = view.notices.size() - shown; i < view.notices.size(); ++i) {
    list.hud.push_back({view.notices[i].text, LevelOf(view.notices[i].level)});
  }
  if (extras.video_lost) list.banner = "VIDEO LOST: the last frame, frozen";
  if (extras.show_help) list.help = KeyHelp();
  return list;
}

}  // namespace igms::control
