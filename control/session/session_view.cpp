// What the operator sees: the platform following the viewer (verification), freezing the
// view on a stereo grab, and unfreezing it.
#include <algorithm>

#include "control/session/cues.h"
#include "control/session/session.h"
#include "control/session/session_internal.h"

namespace igms::control {

using session_detail::ErrorText;
using session_detail::OrientationOfReading;

// ---- verification ----

void Session::On(const ViewerReading& e) {
  const devices::ViewerState& r = e.reading;
  const ViewerOrientation raw = OrientationOfReading(r);
  const uint64_t sequence = r.stamp().sequence();
  if (viewer_ && sequence != 0 && sequence < viewer_sequence_) {
    // The daemon started again, from a new zero where the head is now.
    viewer_zero_.Rezero(*viewer_, raw);
    buttons_.Reset();
    Notice(NoticeLevel::kWarning,
           "the viewer daemon restarted with a new zero; the session keeps the platform where "
           "it had it");
  }
  viewer_sequence_ = sequence;
  viewer_ = viewer_zero_.Apply(raw);
  if (auto c = buttons_.Feed(r.button_left(), r.button_right(), StampTimeNs(r.stamp())))
    Execute({*c, CommandSource::kViewerButtons, e.now_ns}, e.now_ns);
  if (mode_ == Mode::kVerification) CommandPlatform(to_platform_.Ticks(*viewer_), false);
}

void Session::CommandPlatform(const PlatformTicks& ticks, bool force) {
  target_ = ticks;
  if (!peer_up(Peer::kPlatform)) return;
  if (orientation_call_ != 0) {
    pending_ = ticks;  // the newest wins; nothing queues
    return;
  }
  if (!force && last_sent_ && *last_sent_ == ticks) return;
  orientation_call_ = NextCall();
  last_sent_ = ticks;
  out_.push_back(
      SetOrientationEffect{orientation_call_, ticks, options_.steps_per_move, take_control_});
}

void Session::On(const SetOrientationReply& e) {
  if (e.call == 0 || e.call != orientation_call_) return;
  orientation_call_ = 0;
  if (e.error && e.error->code == PERMISSION_DENIED) {
    // Another client controls the platform (or this one may not command it). Keep asking
    // with each reading, so control comes back when that client lets go; never take it
    // unasked.
    last_sent_.reset();
    in_control_ = false;
    take_control_ = false;
    if (!controlled_elsewhere_)
      Notice(NoticeLevel::kError, "the platform does not obey this session: " + e.error->message);
    controlled_elsewhere_ = true;
  } else if (e.error) {
    last_sent_.reset();  // try again with the next reading
    if (!orientation_failing_)
      Notice(NoticeLevel::kWarning, "the platform refused an orientation: " + ErrorText(*e.error));
    orientation_failing_ = true;
  } else {
    orientation_failing_ = false;
    in_control_ = true;
    take_control_ = false;
    if (controlled_elsewhere_) Notice(NoticeLevel::kInfo, "the platform obeys this session again");
    controlled_elsewhere_ = false;
  }
  if (pending_) {
    const PlatformTicks next = *pending_;
    pending_.reset();
    CommandPlatform(next, false);
  }
  if (mode_ == Mode::kFreezing) MaybeGrab(false);
}

void Session::On(const PlatformReading& e) {
  const uint64_t sequence = e.reading.stamp().sequence();
  const bool restarted = platform_sequence_ != 0 && sequence != 0 && sequence < platform_sequence_;
  platform_sequence_ = sequence;
  if (restarted) return PlatformBack("the platform daemon restarted with a new zero");
  if (mode_ != Mode::kFreezing || orientation_call_ != 0) return;
  settled_readings_ = e.reading.moving() ? 0 : settled_readings_ + 1;
  MaybeGrab(false);
}

// ---- freeze ----

void Session::Freeze(int64_t now_ns) {
  Play(cues::kCameraClick);
  Play(cues::kFreezing);
  pending_.reset();  // stop commanding; one already sent is waited for
  settled_readings_ = 0;
  freeze_started_ns_ = now_ns;
  SetMode(Mode::kFreezing);
  MaybeGrab(false);
}

void Session::MaybeGrab(bool timed_out) {
  if (mode_ != Mode::kFreezing) return;
  if (!peer_up(Peer::kPlatform)) {
    Notice(NoticeLevel::kWarning, "the platform is not connected: grabbing where it is");
    return Grab();
  }
  if (timed_out) {
    Notice(NoticeLevel::kWarning, "the platform did not report it had stopped within " +
                                      std::to_string(options_.settle_timeout_ns / 1000000) +
                                      " ms: grabbing anyway");
    return Grab();
  }
  if (orientation_call_ == 0 && settled_readings_ >= options_.settle_readings) Grab();
}

void Session::Grab() {
  grab_call_ = NextCall();
  SetMode(Mode::kGrabbing);
  out_.push_back(GrabEffect{grab_call_});
}

void Session::On(const GrabReply& e) {
  if (e.call == 0) return;
  if (e.call == regrab_call_) {
    regrab_call_ = 0;
    if (const auto* err = std::get_if<CallError>(&e.result)) {
      Notice(NoticeLevel::kError, "grabbing again failed: " + ErrorText(*err));
      return LocateEnded();
    }
    frozen_->grab = std::get<video::GrabResponse>(e.result);
    locate_request_.set_frame_id(frozen_->grab.frame_id());
    return SendLocate();
  }
  if (e.call != grab_call_ || mode_ != Mode::kGrabbing) return;
  grab_call_ = 0;
  if (const auto* err = std::get_if<CallError>(&e.result)) {
    Notice(NoticeLevel::kError, "freeze failed, the video server could not grab: " +
                                    ErrorText(*err) + "; back to verification");
    SetMode(Mode::kVerification);
    if (viewer_) CommandPlatform(to_platform_.Ticks(*viewer_), false);
    return;
  }
  FrozenView view;
  view.grab = std::get<video::GrabResponse>(e.result);
  const size_t n = calibration_.platform ? calibration_.platform->joints.size() : 3;
  view.joints.assign(n, 0.0);
  const auto& joints = view.grab.pose().joints_rad();
  for (int i = 0; i < joints.size() && static_cast<size_t>(i) < n; ++i) view.joints[i] = joints[i];
  view.left_P = LeftCameraAt(view.joints);
  view.right_P = RightCameraAt(view.joints);
  const auto frame =
      CameraFrameOf(geometry::ProjectiveCamera(view.left_P, calibration_.left.image_size));
  view.left_frame = frame.value_or(CameraFrame{});
  frozen_ = view;
  target_ = to_platform_.TicksOf(view.joints);
  pointer_ = view.left_frame.OnAxis(options_.pointer_start_depth);
  drive_time_ns_.reset();
  drive_ = {};
  SetMode(Mode::kModelBuilding);
}

// ---- unfreeze ----

void Session::Unfreeze() {
  Play(cues::kUnfreezing);
  grab_call_ = 0;
  range_call_ = 0;
  frozen_.reset();
  pointer_.reset();
  marks_.clear();
  mark_ids_.clear();
  std::erase_if(undo_, [](const UndoEntry& u) { return u.kind == UndoEntry::kMarkAdded; });
  range_ = 0;
  range_reading_.reset();
  SetMode(Mode::kVerification);
  if (viewer_) CommandPlatform(to_platform_.Ticks(*viewer_), false);
}

}  // namespace igms::control
