// Building models: identifying a box or cylinder from the marks (a locate call), and the
// session's models with removal, undo and wireframe.
#include <algorithm>

#include "control/session/cues.h"
#include "control/session/session.h"
#include "control/session/session_internal.h"

namespace igms::control {

using session_detail::ErrorText;

// ---- identify ----

void Session::Identify(object::ObjectType type, int64_t now_ns) {
  if (!peer_up(Peer::kObject)) {
    Notice(NoticeLevel::kError, "cannot locate: " + Address(Peer::kObject) + " is not connected");
    return;
  }
  Play(type == object::OBJECT_TYPE_BOX ? cues::kModelingAsBox : cues::kModelingAsCylinder);
  Play(cues::kLocatingObject);
  locate_request_.Clear();
  locate_request_.set_type(type);
  for (const auto& m : marks_) *locate_request_.add_marks() = ToVec3(m);
  locate_request_.set_frame_id(frozen_->grab.frame_id());
  locate_request_.set_range(range_);
  // The models built so far: one in front hides part of this object (a pipe on the block
  // marked), and its edges are not this object's. Boxes go without their texture.
  for (const SessionModel& m : models_) {
    if (m.removed) continue;
    object::KnownSolid* k = locate_request_.add_known();
    k->set_name(std::string(m.type == object::OBJECT_TYPE_BOX ? "box " : "cylinder ") +
                std::to_string(m.id));
    k->set_type(m.type);
    if (m.type == object::OBJECT_TYPE_BOX) {
      *k->mutable_box() = m.box;
      k->mutable_box()->clear_texture_png();
    } else {
      *k->mutable_cylinder() = m.cylinder;
    }
  }
  locate_started_ns_ = now_ns;
  please_wait_said_ = false;
  resent_ = false;
  failure_detail_.clear();
  SetMode(Mode::kLocating);
  SendLocate();
}

void Session::SendLocate() {
  locate_call_ = NextCall();
  out_.push_back(LocateEffect{locate_call_, locate_request_});
}

void Session::LocateEnded() {
  locate_call_ = 0;
  SetMode(Mode::kAwaitingType);
}

void Session::On(const LocateReply& e) {
  if (e.call == 0 || e.call != locate_call_ || mode_ != Mode::kLocating) return;
  locate_call_ = 0;
  if (const auto* err = std::get_if<CallError>(&e.result)) {
    if (err->code == NOT_FOUND && !resent_) {
      // The video server no longer holds the frame: grab again (the platform has not moved)
      // and send the same marks once more.
      resent_ = true;
      Notice(NoticeLevel::kWarning, "the video server no longer holds frame " +
                                        std::to_string(locate_request_.frame_id()) +
                                        ": grabbing again at the same pose");
      regrab_call_ = NextCall();
      out_.push_back(GrabEffect{regrab_call_});
      return;
    }
    Notice(NoticeLevel::kError, "locating failed: " + ErrorText(*err));
    return LocateEnded();
  }
  const object::LocateResponse& r = std::get<object::LocateResponse>(e.result);
  if (!r.found()) {
    failure_detail_ = r.detail();
    out_.push_back(SpeakFailureEffect{r.reason()});
    Notice(NoticeLevel::kWarning,
           "object not found (" + object::FailureReason_Name(r.reason()) + "): " + r.detail());
    return LocateEnded();
  }
  SessionModel model;
  model.id = ++last_model_id_;
  model.type = r.type() != object::OBJECT_TYPE_UNSPECIFIED ? r.type() : locate_request_.type();
  model.cylinder = r.cylinder();
  model.box = r.box();
  model.left_P_at_grab = frozen_->left_P;
  models_.push_back(model);
  Provenance provenance;
  provenance.grab = frozen_->grab;
  provenance.request = locate_request_;
  provenance.request.clear_known();  // the database holds those models already
  provenance.response = r;
  provenance.range = range_reading_;
  out_.push_back(StoreModelEffect{model, std::move(provenance)});
  undo_.push_back({UndoEntry::kModelAdded, model.id});
  Play(cues::kBellTree);
  marks_.clear();
  mark_ids_.clear();
  std::erase_if(undo_, [](const UndoEntry& u) { return u.kind == UndoEntry::kMarkAdded; });
  range_ = 0;
  range_reading_.reset();
  SetMode(Mode::kModelBuilding);
}

void Session::On(const TickEvent& e) {
  if (welcome_at_ns_ && e.now_ns >= *welcome_at_ns_) {
    welcome_at_ns_.reset();
    Play(cues::kWelcome);
  }
  if (mode_ == Mode::kLocating && !please_wait_said_ &&
      e.now_ns - locate_started_ns_ >= options_.please_wait_after_ns) {
    please_wait_said_ = true;
    Play(cues::kPleaseWait);
  }
  if (mode_ == Mode::kFreezing && e.now_ns - freeze_started_ns_ >= options_.settle_timeout_ns)
    MaybeGrab(true);
}

// ---- models ----

void Session::RemoveModel() {
  const SessionModel* chosen = nullptr;
  if (pointer_) {
    for (auto it = models_.rbegin(); it != models_.rend() && !chosen; ++it) {
      if (it->removed) continue;
      const bool inside = it->type == object::OBJECT_TYPE_BOX
                              ? BoxContains(it->box, *pointer_)
                              : CylinderContains(it->cylinder, *pointer_);
      if (inside) chosen = &*it;
    }
  }
  for (auto it = models_.rbegin(); it != models_.rend() && !chosen; ++it)
    if (!it->removed) chosen = &*it;
  if (!chosen) {
    Notice(NoticeLevel::kInfo, "no model to remove");
    return;
  }
  const uint64_t id = chosen->id;
  std::find_if(models_.begin(), models_.end(), [&](const SessionModel& m) {
    return m.id == id;
  })->removed = true;
  Play(cues::kRemovingModel);
  out_.push_back(RemoveModelEffect{id});
  undo_.push_back({UndoEntry::kModelRemoved, id});
}

void Session::Undo() {
  if (undo_.empty()) {
    Notice(NoticeLevel::kInfo, "nothing to undo");
    return;
  }
  const UndoEntry u = undo_.back();
  undo_.pop_back();
  auto model = std::find_if(models_.begin(), models_.end(),
                            [&](const SessionModel& m) { return m.id == u.id; });
  switch (u.kind) {
    case UndoEntry::kMarkAdded:
      // Mark entries are dropped whenever their marks go, so this is the last mark.
      undo_.push_back(u);
      Unmark(true);
      return;
    case UndoEntry::kModelAdded:
      if (model == models_.end()) return;
      model->removed = true;
      Play(cues::kRemovingModel);
      out_.push_back(RemoveModelEffect{u.id, true});
      Notice(NoticeLevel::kInfo, "undone: model " + std::to_string(u.id) + " added");
      return;
    case UndoEntry::kModelRemoved:
      if (model == models_.end()) return;
      model->removed = false;
      out_.push_back(RestoreModelEffect{u.id});
      Notice(NoticeLevel::kInfo, "undone: model " + std::to_string(u.id) + " removed");
      return;
  }
}

void Session::On(const ModelsLoaded& e) {
  for (const SessionModel& m : e.models) {
    models_.push_back(m);
    if (auto it = e.grab_joints.find(m.id); it != e.grab_joints.end()) {
      models_.back().left_P_at_grab = LeftCameraAt(it->second);
    }
    last_model_id_ = std::max(last_model_id_, m.id);
  }
}

void Session::SetWireframe(bool wireframe) {
  if (wireframe == wireframe_) return;
  wireframe_ = wireframe;
  out_.push_back(DisplayEffect{wireframe_});
}

}  // namespace igms::control
