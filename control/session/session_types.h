// What goes into the session's state machine (events) and what comes out (effects).
//
// Events are everything the outside world tells the session: readings with their stamps,
// the replies of the calls it asked for (each carries the `call` id of its effect, so a
// reply the session no longer waits for is ignored), peers lost and back, device link
// states, timer ticks, and commands from sources that need no filtering (the window's keys
// and mouse, scripts). Each event carries `now_ns`: the caller's CLOCK_MONOTONIC when it
// happened. The session has no clock, no socket and no thread of its own.
//
// Effects are what the session wants done, in order: calls to peers, sounds, the voice
// grammar's state, the database's changes, the display mode, notices for the operator. The
// I/O side (the control client's app) carries them out and answers calls with events.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "control/session/commands.h"
#include "control/session/orientation.h"
#include "igms/common.pb.h"
#include "igms/devices.pb.h"
#include "igms/object.pb.h"
#include "igms/sound.pb.h"
#include "igms/video.pb.h"

namespace igms::control {

// Every peer of the session (the lab file's processes.*).
enum class Peer { kVideo, kObject, kPlatform, kViewer, kJoystick, kSound, kVoice, kRanger };
inline constexpr Peer kAllPeers[] = {Peer::kVideo,  Peer::kObject,   Peer::kPlatform,
                                     Peer::kViewer, Peer::kJoystick, Peer::kSound,
                                     Peer::kVoice,  Peer::kRanger};
// "video", "object", ... (the lab file's process names).
std::string_view PeerName(Peer peer);
// Video, object, platform, viewer and joystick are required; sound, voice, ranger optional.
bool IsRequired(Peer peer);
// Servers (video, object, sound) versus device daemons (the rest).
bool IsDaemon(Peer peer);

// A model the session holds: its id (the session's, from 1 or after those loaded) and the
// object server's solid. `removed` models stay, so undo can bring them back.
struct SessionModel {
  uint64_t id = 0;
  object::ObjectType type = object::OBJECT_TYPE_UNSPECIFIED;
  object::CylinderModel cylinder;
  object::BoxModel box;
  bool removed = false;
  // The left camera at the grab it was located in (the box's texture patch is that image's):
  // zero when unknown (a model of a continued session).
  Eigen::Matrix<double, 3, 4> left_P_at_grab = Eigen::Matrix<double, 3, 4>::Zero();
};

// Where a stored model came from, for the database.
struct Provenance {
  video::GrabResponse grab;                   // frame id, capture times, the platform pose
  object::LocateRequest request;              // type, marks, frame id, range (world units)
  object::LocateResponse response;            // residuals, timings, the range report
  std::optional<devices::RangerState> range;  // the ranger's reading, when one was taken
};

// ---- events ----

struct PeerReport {
  Peer peer = Peer::kVideo;
  std::string address;  // host:port, for messages
  bool up = false;
  std::string why;  // when not up
};
// The start-up checks' outcome (thesis 2.4): which peers answered.
struct StartEvent {
  std::vector<PeerReport> peers;
  int64_t now_ns = 0;
};
struct PeerUpEvent {
  Peer peer = Peer::kVideo;
  int64_t now_ns = 0;
};
struct PeerDownEvent {
  Peer peer = Peer::kVideo;
  std::string why;
  int64_t now_ns = 0;
};
// A daemon's serial link state, polled at 1 Hz.
struct DeviceLinkEvent {
  Peer peer = Peer::kViewer;
  devices::LinkState state = devices::LINK_STATE_UNSPECIFIED;
  std::string message;
  int64_t now_ns = 0;
};
struct ViewerReading {
  devices::ViewerState reading;
  int64_t now_ns = 0;
};
struct JoystickReading {
  devices::JoystickState reading;
  int64_t now_ns = 0;
};
struct PlatformReading {
  devices::PlatformState reading;
  int64_t now_ns = 0;
};
struct VoiceReading {
  devices::VoiceState reading;
  int64_t now_ns = 0;
};
// The voice daemon's Live was (re)subscribed; its Status counted `newest_sequence`
// readings just before.
struct VoiceSubscribed {
  uint64_t newest_sequence = 0;
  int64_t now_ns = 0;
};

struct CallError {
  ErrorCode code = ERROR_CODE_UNSPECIFIED;
  std::string message;
};
struct SetOrientationReply {
  uint64_t call = 0;
  std::optional<CallError> error;
  int64_t now_ns = 0;
};
struct GrabReply {
  uint64_t call = 0;
  std::variant<video::GrabResponse, CallError> result;
  int64_t now_ns = 0;
};
struct RangeReply {
  uint64_t call = 0;
  std::variant<devices::RangerState, CallError> result;
  int64_t now_ns = 0;
};
struct LocateReply {
  uint64_t call = 0;
  std::variant<object::LocateResponse, CallError> result;
  int64_t now_ns = 0;
};
struct TickEvent {
  int64_t now_ns = 0;
};
struct CommandEvent {
  Command command;
  int64_t now_ns = 0;
};
struct PointerDriveEvent {
  PointerDrive drive;
  int64_t now_ns = 0;
};
// Models of a continued session (the database), in the order they were added.
struct ModelsLoaded {
  std::vector<SessionModel> models;
  int64_t now_ns = 0;
  // Model id -> the platform's joints at the grab it was located in (the database's
  // provenance), for the models whose grab is known: their left camera then places a box's
  // texture patch, as for a model of this session.
  std::map<uint64_t, std::vector<double>> grab_joints;
};

using Event = std::variant<StartEvent, PeerUpEvent, PeerDownEvent, DeviceLinkEvent, ViewerReading,
                           JoystickReading, PlatformReading, VoiceReading, VoiceSubscribed,
                           SetOrientationReply, GrabReply, RangeReply, LocateReply, TickEvent,
                           CommandEvent, PointerDriveEvent, ModelsLoaded>;

// ---- effects ----

struct SetOrientationEffect {  // PlatformService.SetOrientation
  uint64_t call = 0;
  PlatformTicks ticks;
  uint32_t steps_per_move = 0;
  bool take_control = false;  // take control of the platform from the client holding it
};
struct GrabEffect {  // VideoService.Grab
  uint64_t call = 0;
};
struct SetOperatorStateEffect {  // VoiceService.SetOperatorState
  devices::OperatorState state = devices::VERIFICATION;
};
struct PlaySoundEffect {  // SoundService.Play by the manifest's key
  std::string key;
  sound::Priority priority = sound::PRIORITY_NORMAL;
};
// SoundService.Play of the bank entry whose `reason` is this reason's enum value name.
struct SpeakFailureEffect {
  object::FailureReason reason = object::FAILURE_NONE;
};
struct RangeEffect {  // RangerService.Range
  uint64_t call = 0;
};
struct LocateEffect {  // ObjectService.Locate, asynchronously
  uint64_t call = 0;
  object::LocateRequest request;
};
struct StoreModelEffect {
  SessionModel model;
  Provenance provenance;
};
struct RemoveModelEffect {  // a mark of removal: undo may restore it
  uint64_t id = 0;
  bool undo = false;  // taking back the model's addition (the database records an undo)
};
struct RestoreModelEffect {
  uint64_t id = 0;
};
struct DisplayEffect {
  bool wireframe = false;
};
enum class NoticeLevel { kInfo, kWarning, kError };
struct NoticeEffect {  // text for the operator's display and the log
  NoticeLevel level = NoticeLevel::kInfo;
  std::string text;
};
struct ExitEffect {  // the session cannot start
  int code = 1;
  std::string message;
};

using Effect =
    std::variant<SetOrientationEffect, GrabEffect, SetOperatorStateEffect, PlaySoundEffect,
                 SpeakFailureEffect, RangeEffect, LocateEffect, StoreModelEffect, RemoveModelEffect,
                 RestoreModelEffect, DisplayEffect, NoticeEffect, ExitEffect>;
using Effects = std::vector<Effect>;

}  // namespace igms::control
