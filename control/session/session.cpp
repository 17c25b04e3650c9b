// The session: made from its options, events dispatched to their handlers, the effects it
// emits, the start, and the commands (session.h; the modes' tables in session_modes.cpp).
#include "control/session/session.h"

#include <algorithm>

#include "common/geometry/platform.h"
#include "control/session/cues.h"
#include "control/session/session_internal.h"

namespace igms::control {

using session_detail::Index;

std::unique_ptr<Session> Session::Make(const SessionOptions& options,
                                       const calibration::StereoCalibration& calibration,
                                       std::string* error) {
  std::string why;
  if (!options.Check(&why)) {
    if (error) *error = "session options: " + why;
    return nullptr;
  }
  auto to_platform = ViewerToPlatform::Make(calibration, options.all_axes);
  if (!to_platform.ok()) {
    if (error) *error = to_platform.error();
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
