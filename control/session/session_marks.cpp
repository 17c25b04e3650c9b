// Pointing in the frozen view: driving the pointer, ranging along it, and the marks the
// operator leaves at its tip.
#include <algorithm>

#include "control/session/cues.h"
#include "control/session/session.h"
#include "control/session/session_internal.h"

namespace igms::control {

using session_detail::ErrorText;

// ---- pointer and range ----

void Session::On(const JoystickReading& e) {
  JoystickInput in = joystick_.Feed(e.reading);
  for (CommandKind c : in.commands) Execute({c, CommandSource::kJoystick, e.now_ns}, e.now_ns);
  Drive(in.drive);
}

void Session::On(const PointerDriveEvent& e) { Drive(e.drive); }

void Session::Drive(const PointerDrive& d) {
  if (!pointer_ || !frozen_ || (mode_ != Mode::kModelBuilding && mode_ != Mode::kAwaitingType)) {
    drive_time_ns_.reset();
    return;
  }
  // The deflection held since the previous reading moved the pointer until this one.
  if (drive_time_ns_ && d.time_ns > *drive_time_ns_) {
    const double dt =
        static_cast<double>(std::min(d.time_ns - *drive_time_ns_, options_.max_drive_step_ns)) *
        1e-9;
    const CameraFrame& f = frozen_->left_frame;
    *pointer_ += options_.pointer_speed * dt *
                 (drive_.right * f.right + drive_.up * f.up() + drive_.forward * f.forward);
  }
  drive_time_ns_ = d.time_ns;
  drive_ = d;
}

void Session::Range() {
  if (!peer_up(Peer::kRanger)) {
    Notice(NoticeLevel::kWarning,
           "no ranger in this session: " + Address(Peer::kRanger) + " is not connected");
    return;
  }
  if (range_call_ != 0) return;  // one measurement at a time
  Play(cues::kRicochet);
  range_call_ = NextCall();
  out_.push_back(RangeEffect{range_call_});
}

void Session::On(const RangeReply& e) {
  if (e.call == 0 || e.call != range_call_) return;
  range_call_ = 0;
  if (!frozen_ || !pointer_) return;
  if (const auto* err = std::get_if<CallError>(&e.result)) {
    Notice(NoticeLevel::kWarning, "ranging failed: " + ErrorText(*err));
    return;
  }
  const devices::RangerState& r = std::get<devices::RangerState>(e.result);
  if (!r.valid() || !(r.range_in() > 0)) {
    Play(cues::kNoEcho);
    Notice(NoticeLevel::kInfo, "no echo: nothing inside the ranger's beam from 2 in to 60 ft");
    return;
  }
  const Beam beam = BeamAt(calibration_, frozen_->joints);
  range_ = r.range_in() * options_.world_units_per_inch;
  range_reading_ = r;
  pointer_ = beam.origin + range_ * beam.axis;
}

// ---- marks ----

void Session::Mark() {
  if (!pointer_ || marks_.size() >= 4) return;
  marks_.push_back(*pointer_);
  mark_ids_.push_back(++last_mark_id_);
  undo_.push_back({UndoEntry::kMarkAdded, last_mark_id_});
  Play(cues::kWoodblock);
  if (marks_.size() == 4) {
    SetMode(Mode::kAwaitingType);
    Play(cues::kBoxOrCylinder, sound::PRIORITY_HIGH);
  }
}

void Session::Unmark(bool play) {
  if (marks_.empty()) {
    Notice(NoticeLevel::kInfo, "no mark to remove");
    return;
  }
  const uint64_t id = mark_ids_.back();
  marks_.pop_back();
  mark_ids_.pop_back();
  std::erase_if(undo_,
                [&](const UndoEntry& u) { return u.kind == UndoEntry::kMarkAdded && u.id == id; });
  if (play) Play(cues::kUnmark);
  if (mode_ == Mode::kAwaitingType) SetMode(Mode::kModelBuilding);
}

void Session::RemovePoints() {
  Play(cues::kRemovingPoints);
  marks_.clear();
  mark_ids_.clear();
  std::erase_if(undo_, [](const UndoEntry& u) { return u.kind == UndoEntry::kMarkAdded; });
  range_ = 0;
  range_reading_.reset();
  if (mode_ == Mode::kAwaitingType) SetMode(Mode::kModelBuilding);
}

}  // namespace igms::control
