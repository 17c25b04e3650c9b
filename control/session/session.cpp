#include "control/session/session.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/geometry/platform.h"
#include "control/session/cues.h"

namespace igms::control {
namespace {

int Index(Peer peer) { return static_cast<int>(peer); }

std::string ErrorText(const CallError& e) {
  return ErrorCode_Name(e.code) + (e.message.empty() ? "" : ": " + e.message);
}

bool LinkGood(devices::LinkState s) { return s == devices::CONNECTED || s == devices::REPLAYING; }

ViewerOrientation OrientationOfReading(const devices::ViewerState& r) {
  return {r.yaw_deg(), r.pitch_deg(), r.roll_deg()};
}

}  // namespace

std::string_view PeerName(Peer peer) {
  switch (peer) {
    case Peer::kVideo:
      return "video";
    case Peer::kObject:
      return "object";
    case Peer::kPlatform:
      return "platform";
    case Peer::kViewer:
      return "viewer";
    case Peer::kJoystick:
      return "joystick";
    case Peer::kSound:
      return "sound";
    case Peer::kVoice:
      return "voice";
    case Peer::kRanger:
      return "ranger";
  }
  return "unknown";
}

bool IsRequired(Peer peer) {
  return peer != Peer::kSound && peer != Peer::kVoice && peer != Peer::kRanger;
}

bool IsDaemon(Peer peer) {
  return peer != Peer::kVideo && peer != Peer::kObject && peer != Peer::kSound;
}

std::string_view ModeName(Mode mode) {
  switch (mode) {
    case Mode::kStarting:
      return "starting";
    case Mode::kVerification:
      return "verification";
    case Mode::kFreezing:
      return "freezing";
    case Mode::kGrabbing:
      return "grabbing";
    case Mode::kModelBuilding:
      return "model building";
    case Mode::kAwaitingType:
      return "awaiting the object type";
    case Mode::kLocating:
      return "locating";
    case Mode::kStopped:
      return "stopped";
  }
  return "unknown";
}

devices::OperatorState OperatorStateOf(Mode mode) {
  switch (mode) {
    case Mode::kFreezing:
    case Mode::kGrabbing:
    case Mode::kModelBuilding:
    case Mode::kLocating:
      return devices::MODEL_BUILDING;
    case Mode::kAwaitingType:
      return devices::AWAITING_OBJECT_TYPE;
    default:
      return devices::VERIFICATION;
  }
}

bool IsValid(Mode mode, CommandKind c) {
  using C = CommandKind;
  const bool display = c == C::kWireframe || c == C::kSolid || c == C::kToggleWireframe;
  switch (mode) {
    case Mode::kStarting:
    case Mode::kStopped:
      return false;
    case Mode::kVerification:
      return display || c == C::kFreeze || c == C::kRemoveModel || c == C::kUndo;
    case Mode::kFreezing:
    case Mode::kGrabbing:
      return display || c == C::kUnfreeze;
    case Mode::kModelBuilding:
      return display || c == C::kUnfreeze || c == C::kRange || c == C::kMark || c == C::kUnmark ||
             c == C::kRemovePoints || c == C::kRemoveModel || c == C::kUndo;
    case Mode::kAwaitingType:
      return display || c == C::kIdentifyBox || c == C::kIdentifyCylinder || c == C::kUnmark ||
             c == C::kRemovePoints || c == C::kUnfreeze || c == C::kUndo;
    case Mode::kLocating:
      return display;
  }
  return false;
}

std::string FailureMessageKey(const sound::ListBankResponse& bank, object::FailureReason reason) {
  const std::string name = object::FailureReason_Name(reason);
  for (const auto& entry : bank.sounds())
    if (!name.empty() && entry.reason() == name) return entry.key();
  return "";
}

std::unique_ptr<Session> Session::Make(const SessionOptions& options,
                                       const calibration::StereoCalibration& calibration,
                                       std::string* error) {
  std::string why;
  if (!options.Check(&why)) {
    if (error) *error = "session options: " + why;
    return nullptr;
  }
  auto to_platform = ViewerToPlatform::Make(calibration, options.all_axes, &why);
  if (!to_platform) {
    if (error) *error = why;
    return nullptr;
  }
  if (!CameraFrameOf(calibration.left.Camera())) {
    if (error) *error = "calibration left.P: the optical axis does not project into the image";
    return nullptr;
  }
  return std::unique_ptr<Session>(new Session(options, calibration, *to_platform));
}

Session::Session(const SessionOptions& options, const calibration::StereoCalibration& calibration,
                 const ViewerToPlatform& to_platform)
    : options_(options),
      calibration_(calibration),
      to_platform_(to_platform),
      buttons_(options.button_hold_ns),
      joystick_(options.stick_dead_band),
      take_control_(options.take_control) {}

Effects Session::Handle(const Event& event) {
  out_.clear();
  std::visit([this](const auto& e) { On(e); }, event);
  return std::move(out_);
}

namespace {

geometry::Matrix34 CameraAt(const geometry::Matrix34& P0,
                            const std::optional<geometry::PlatformModel>& platform,
                            std::span<const double> joints) {
  if (!platform) return P0;
  std::vector<double> q(platform->joints.size(), 0.0);
  std::copy_n(joints.begin(), std::min(joints.size(), q.size()), q.begin());
  return geometry::CameraAtPose(P0, *platform, q);
}

}  // namespace

geometry::Matrix34 Session::LeftCameraAt(std::span<const double> joints) const {
  return CameraAt(calibration_.left.P, calibration_.platform, joints);
}

geometry::Matrix34 Session::RightCameraAt(std::span<const double> joints) const {
  return CameraAt(calibration_.right.P, calibration_.platform, joints);
}

// ---- helpers ----

void Session::Play(const char* key, sound::Priority priority) {
  // A lost sound server never stops a session: its cues are simply not asked for.
  if (!peer_up(Peer::kSound)) return;
  out_.push_back(PlaySoundEffect{key, priority});
}

void Session::Notice(NoticeLevel level, std::string text) {
  out_.push_back(NoticeEffect{level, std::move(text)});
}

std::string Session::Address(Peer peer) const {
  const std::string& a = addresses_[Index(peer)];
  return std::string(PeerName(peer)) + (a.empty() ? "" : " (" + a + ")");
}

void Session::SetMode(Mode mode) {
  const devices::OperatorState before = OperatorStateOf(mode_);
  mode_ = mode;
  const devices::OperatorState after = OperatorStateOf(mode_);
  // The voice grammar follows the system's state (fixing the flaw of thesis 2.1.6): told
  // at every change, so a command from the buttons or the keys never leaves it behind.
  if (before != after && peer_up(Peer::kVoice)) out_.push_back(SetOperatorStateEffect{after});
}

// ---- start ----

void Session::On(const StartEvent& e) {
  if (mode_ != Mode::kStarting) return;
  std::vector<std::string> missing;
  for (const PeerReport& p : e.peers) {
    addresses_[Index(p.peer)] = p.address;
    peer_up_[Index(p.peer)] = p.up;
    if (p.up) continue;
    const std::string what = Address(p.peer) + (p.why.empty() ? "" : ": " + p.why);
    if (IsRequired(p.peer)) {
      missing.push_back(what);
    } else {
      Notice(NoticeLevel::kWarning, "optional peer missing, going on without it: " + what);
    }
  }
  for (Peer p : kAllPeers) {
    const bool reported = std::any_of(e.peers.begin(), e.peers.end(),
                                      [&](const PeerReport& r) { return r.peer == p; });
    if (!reported && IsRequired(p)) missing.push_back(Address(p) + ": not in the lab file");
  }
  if (missing.empty()) return Begin(e.now_ns);
  std::string list;
  for (const auto& m : missing) list += (list.empty() ? "" : "; ") + m;
  if (options_.wait_for_peers) {
    Notice(NoticeLevel::kWarning, "waiting for required peers: " + list);
    return;
  }
  mode_ = Mode::kStopped;
  out_.push_back(ExitEffect{1, "required peers missing: " + list});
}

void Session::Begin(int64_t now_ns) {
  mode_ = Mode::kVerification;
  if (peer_up(Peer::kVoice)) out_.push_back(SetOperatorStateEffect{devices::VERIFICATION});
  Play(cues::kIntroductionMusic);
  welcome_at_ns_ = now_ns + options_.welcome_after_ns;
  Notice(NoticeLevel::kInfo, "session started: verification");
  if (viewer_) CommandPlatform(to_platform_.Ticks(*viewer_), false);
}

// ---- health ----

void Session::On(const PeerUpEvent& e) {
  const int i = Index(e.peer);
  if (peer_up_[i]) return;
  peer_up_[i] = true;
  if (mode_ == Mode::kStarting) {
    for (Peer p : kAllPeers)
      if (IsRequired(p) && !peer_up(p)) return;
    return Begin(e.now_ns);
  }
  Notice(NoticeLevel::kInfo, Address(e.peer) + " is back");
  Play(cues::kServerBack);
  switch (e.peer) {
    case Peer::kPlatform:
      PlatformBack("the platform daemon is back");
      break;
    case Peer::kVoice:
      out_.push_back(SetOperatorStateEffect{OperatorStateOf(mode_)});
      break;
    case Peer::kJoystick:
      joystick_.Reset();
      break;
    case Peer::kViewer:
      buttons_.Reset();
      break;
    default:
      break;
  }
}

void Session::On(const PeerDownEvent& e) {
  const int i = Index(e.peer);
  if (!peer_up_[i]) return;
  peer_up_[i] = false;
  Play(cues::kServerLost);  // after marking it down: the sound server's own loss is silent
  Notice(IsRequired(e.peer) ? NoticeLevel::kError : NoticeLevel::kWarning,
         "lost " + Address(e.peer) + (e.why.empty() ? "" : ": " + e.why) + "; reconnecting");
  if (e.peer == Peer::kPlatform) {
    // Its answer will not come; the platform is commanded afresh when it is back.
    orientation_call_ = 0;
    pending_.reset();
    last_sent_.reset();
    // The daemon may still count the lost connection as the holder (a half-dead one is
    // noticed only at its idle timeout): the reconnected session takes control back.
    if (in_control_) take_control_ = true;
    in_control_ = false;
  }
}

void Session::On(const DeviceLinkEvent& e) {
  const int i = Index(e.peer);
  const bool good = LinkGood(e.state);
  if (good == link_good_[i]) return;
  link_good_[i] = good;
  const std::string what = std::string(PeerName(e.peer)) + " device " +
                           devices::LinkState_Name(e.state) +
                           (e.message.empty() ? "" : ": " + e.message);
  if (good) {
    Notice(NoticeLevel::kInfo, what);
    Play(cues::kDeviceBack);
  } else {
    Notice(NoticeLevel::kWarning, what);
    Play(cues::kDeviceLost);
  }
}

void Session::PlatformBack(const std::string& why) {
  // A restarted platform daemon has a new zero: put the platform where the session had it.
  orientation_call_ = 0;
  pending_.reset();
  last_sent_.reset();
  std::optional<PlatformTicks> where;
  if (frozen_) {
    where = to_platform_.TicksOf(frozen_->joints);
  } else if (target_) {
    where = target_;
  }
  if (!where) return;
  target_ = where;
  Notice(NoticeLevel::kWarning, why + ": putting the platform back where the session had it (" +
                                    std::to_string(where->yaw) + ", " +
                                    std::to_string(where->pitch) + ", " +
                                    std::to_string(where->roll) + " ticks)");
  CommandPlatform(*where, true);
}

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
    const double dt = std::min(d.time_ns - *drive_time_ns_, options_.max_drive_step_ns) * 1e-9;
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

// ---- commands ----

void Session::On(const VoiceSubscribed& e) { voice_.Subscribed(e.newest_sequence); }

void Session::On(const VoiceReading& e) {
  if (auto c = voice_.Feed(e.reading)) Execute({*c, CommandSource::kVoice, e.now_ns}, e.now_ns);
}

void Session::On(const CommandEvent& e) { Execute(e.command, e.now_ns); }

void Session::Execute(const Command& command, int64_t now_ns) {
  if (!IsValid(mode_, command.kind)) {
    Notice(NoticeLevel::kInfo, std::string(CommandName(command.kind)) + " (" +
                                   std::string(SourceName(command.source)) +
                                   ") is not valid while " + std::string(ModeName(mode_)));
    return;
  }
  switch (command.kind) {
    case CommandKind::kFreeze:
      return Freeze(now_ns);
    case CommandKind::kUnfreeze:
      return Unfreeze();
    case CommandKind::kRange:
      return Range();
    case CommandKind::kMark:
      return Mark();
    case CommandKind::kUnmark:
      return Unmark(true);
    case CommandKind::kRemovePoints:
      return RemovePoints();
    case CommandKind::kIdentifyBox:
      return Identify(object::OBJECT_TYPE_BOX, now_ns);
    case CommandKind::kIdentifyCylinder:
      return Identify(object::OBJECT_TYPE_CYLINDER, now_ns);
    case CommandKind::kWireframe:
      return SetWireframe(true);
    case CommandKind::kSolid:
      return SetWireframe(false);
    case CommandKind::kToggleWireframe:
      return SetWireframe(!wireframe_);
    case CommandKind::kRemoveModel:
      return RemoveModel();
    case CommandKind::kUndo:
      return Undo();
  }
}

}  // namespace igms::control
