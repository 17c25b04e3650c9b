// The operator's session: the control software of Cooke, *Interactive Graphical Model
// Building using Virtual Reality*, section 2.4 and figure 2-5, as a state machine with no
// I/O inside. Events go in (session_types.h), effects come out; the caller's clock, sockets
// and threads stay outside, so every transition is a unit test (tests/control/session).
// States, commands per source and effects: docs/control.md.
//
//   kStarting ---- every required peer up ----> kVerification (slaved to the viewer)
//   kVerification -- freeze --> kFreezing (platform settling) --> kGrabbing --> kModelBuilding
//   kModelBuilding -- fourth mark --> kAwaitingType -- box/cylinder --> kLocating
//   kLocating -- found --> kModelBuilding;  not found / failed --> kAwaitingType
//   unfreeze (freezing, grabbing, model building, awaiting type) --> kVerification
//   kStopped: a required peer was missing at start (ExitEffect).
//
// A command not valid in the state (IsValid) is refused with a notice, whatever its source.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/calibration/calibration_file.h"
#include "common/geometry/camera.h"
#include "control/session/commands.h"
#include "control/session/inputs.h"
#include "control/session/orientation.h"
#include "control/session/pointer.h"
#include "control/session/session_options.h"
#include "control/session/session_types.h"

namespace igms::control {

enum class Mode {
  kStarting,
  kVerification,
  kFreezing,
  kGrabbing,
  kModelBuilding,
  kAwaitingType,
  kLocating,
  kStopped,
};
std::string_view ModeName(Mode mode);
// The voice grammar's state for a mode (verification for starting and stopped).
devices::OperatorState OperatorStateOf(Mode mode);
// Whether a command may act in a mode (the voice grammars of docs/voice.md, plus undo and
// the display toggle; nothing while starting, locating allows only the display).
bool IsValid(Mode mode, CommandKind command);

// The frozen view: the grab and the cameras at its pose.
struct FrozenView {
  video::GrabResponse grab;
  std::vector<double> joints;  // the grab's joint angles (radians), one per model joint
  geometry::Matrix34 left_P = geometry::Matrix34::Zero();
  geometry::Matrix34 right_P = geometry::Matrix34::Zero();
  CameraFrame left_frame;
};

class Session {
 public:
  // Null with `error` when the options or the calibration's platform will not do.
  static std::unique_ptr<Session> Make(const SessionOptions& options,
                                       const calibration::StereoCalibration& calibration,
                                       std::string* error = nullptr);

  Effects Handle(const Event& event);

  Mode mode() const { return mode_; }
  bool peer_up(Peer peer) const { return peer_up_[static_cast<int>(peer)]; }
  const std::optional<FrozenView>& frozen() const { return frozen_; }
  const std::optional<Eigen::Vector3d>& pointer() const { return pointer_; }
  // The viewer's orientation as the session uses it (re-zeroed after a restarted daemon).
  const std::optional<ViewerOrientation>& viewer() const { return viewer_; }
  const std::vector<Eigen::Vector3d>& marks() const { return marks_; }
  const std::vector<SessionModel>& models() const { return models_; }
  bool wireframe() const { return wireframe_; }
  // The range (world units along the beam) that goes into the next locate; 0 = none.
  double range() const { return range_; }
  // The last locate failure's detail, for the display.
  const std::string& failure_detail() const { return failure_detail_; }
  // The orientation the session commands (verification) or holds (frozen).
  const std::optional<PlatformTicks>& platform_target() const { return target_; }
  const ViewerToPlatform& viewer_to_platform() const { return to_platform_; }
  // The cameras at a platform pose (joint angles in radians, as a LiveFrame's or a grab's
  // PlatformPose gives them): the graphics follow the pose each frame was taken at.
  geometry::Matrix34 LeftCameraAt(std::span<const double> joints) const;
  geometry::Matrix34 RightCameraAt(std::span<const double> joints) const;

 private:
  Session(const SessionOptions& options, const calibration::StereoCalibration& calibration,
          const ViewerToPlatform& to_platform);

  void On(const StartEvent& e);
  void On(const PeerUpEvent& e);
  void On(const PeerDownEvent& e);
  void On(const DeviceLinkEvent& e);
  void On(const ViewerReading& e);
  void On(const JoystickReading& e);
  void On(const PlatformReading& e);
  void On(const VoiceReading& e);
  void On(const VoiceSubscribed& e);
  void On(const SetOrientationReply& e);
  void On(const GrabReply& e);
  void On(const RangeReply& e);
  void On(const LocateReply& e);
  void On(const TickEvent& e);
  void On(const CommandEvent& e);
  void On(const PointerDriveEvent& e);
  void On(const ModelsLoaded& e);

  void Execute(const Command& command, int64_t now_ns);
  void Begin(int64_t now_ns);
  void Freeze(int64_t now_ns);
  void MaybeGrab(bool timed_out);
  void Grab();
  void Unfreeze();
  void Mark();
  void Unmark(bool play);
  void RemovePoints();
  void Range();
  void Identify(object::ObjectType type, int64_t now_ns);
  void SendLocate();
  void LocateEnded();
  void RemoveModel();
  void Undo();
  void SetWireframe(bool wireframe);
  void Drive(const PointerDrive& drive);
  void CommandPlatform(const PlatformTicks& ticks, bool force);
  void PlatformBack(const std::string& why);
  void SetMode(Mode mode);
  void Play(const char* key, sound::Priority priority = sound::PRIORITY_NORMAL);
  void Notice(NoticeLevel level, std::string text);
  std::string Address(Peer peer) const;
  uint64_t NextCall() { return ++last_call_; }

  SessionOptions options_;
  calibration::StereoCalibration calibration_;
  ViewerToPlatform to_platform_;
  ViewerButtonFilter buttons_;
  JoystickMapper joystick_;
  VoiceFilter voice_;
  ViewerZero viewer_zero_;

  Effects out_;
  Mode mode_ = Mode::kStarting;
  bool peer_up_[8] = {};
  bool link_good_[8] = {true, true, true, true, true, true, true, true};
  std::string addresses_[8];
  uint64_t last_call_ = 0;
  std::optional<int64_t> welcome_at_ns_;

  // Verification.
  std::optional<ViewerOrientation> viewer_;  // the session's (re-zeroed) orientation
  uint64_t viewer_sequence_ = 0;
  bool viewer_restarted_ = false;
  std::optional<PlatformTicks> target_;     // what the session wants the platform at
  std::optional<PlatformTicks> last_sent_;  // the newest SetOrientation sent
  uint64_t orientation_call_ = 0;           // in flight, 0 = none
  std::optional<PlatformTicks> pending_;    // the newest wanted while one is in flight
  bool orientation_failing_ = false;
  uint64_t platform_sequence_ = 0;
  // The platform's one controlling client: whether this session holds control (its last
  // command was obeyed), whether the next command takes it, and whether another client
  // holds it (the operator has been told).
  bool in_control_ = false;
  bool take_control_ = false;
  bool controlled_elsewhere_ = false;

  // Freeze.
  int64_t freeze_started_ns_ = 0;
  int settled_readings_ = 0;
  uint64_t grab_call_ = 0;
  std::optional<FrozenView> frozen_;

  // Pointer, range, marks.
  std::optional<Eigen::Vector3d> pointer_;
  std::optional<int64_t> drive_time_ns_;
  PointerDrive drive_;
  uint64_t range_call_ = 0;
  double range_ = 0.0;
  std::optional<devices::RangerState> range_reading_;
  std::vector<Eigen::Vector3d> marks_;
  std::vector<uint64_t> mark_ids_;
  uint64_t last_mark_id_ = 0;

  // Identify.
  uint64_t locate_call_ = 0;
  uint64_t regrab_call_ = 0;
  object::LocateRequest locate_request_;
  int64_t locate_started_ns_ = 0;
  bool please_wait_said_ = false;
  bool resent_ = false;
  std::string failure_detail_;

  // Models and undo.
  std::vector<SessionModel> models_;
  uint64_t last_model_id_ = 0;
  bool wireframe_ = false;
  struct UndoEntry {
    enum Kind { kMarkAdded, kModelAdded, kModelRemoved } kind;
    uint64_t id;  // the mark's or the model's
  };
  std::vector<UndoEntry> undo_;
};

// The bank entry that speaks a failure reason: the one whose `reason` is the reason's enum
// value name (FAILURE_MARKS_DEGENERATE, ...). Empty when the bank has none.
std::string FailureMessageKey(const sound::ListBankResponse& bank, object::FailureReason reason);

}  // namespace igms::control
