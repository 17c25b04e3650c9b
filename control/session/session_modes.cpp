// The session's tables: the peers by name, the modes and the operator state each one tells
// the voice grammar, and which commands each mode accepts (docs/control.md).
#include "control/session/session.h"

namespace igms::control {

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

}  // namespace igms::control
