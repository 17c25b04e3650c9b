#include "control/session/commands.h"

namespace igms::control {

std::string_view CommandName(CommandKind kind) {
  switch (kind) {
    case CommandKind::kFreeze:
      return "freeze";
    case CommandKind::kUnfreeze:
      return "unfreeze";
    case CommandKind::kRange:
      return "range";
    case CommandKind::kMark:
      return "mark";
    case CommandKind::kUnmark:
      return "unmark";
    case CommandKind::kRemovePoints:
      return "remove_points";
    case CommandKind::kIdentifyBox:
      return "identify_box";
    case CommandKind::kIdentifyCylinder:
      return "identify_cylinder";
    case CommandKind::kWireframe:
      return "wireframe";
    case CommandKind::kSolid:
      return "solid";
    case CommandKind::kToggleWireframe:
      return "toggle_wireframe";
    case CommandKind::kRemoveModel:
      return "remove_model";
    case CommandKind::kUndo:
      return "undo";
  }
  return "unknown";
}

std::string_view SourceName(CommandSource source) {
  switch (source) {
    case CommandSource::kViewerButtons:
      return "viewer_buttons";
    case CommandSource::kJoystick:
      return "joystick";
    case CommandSource::kVoice:
      return "voice";
    case CommandSource::kKeyboard:
      return "keyboard";
    case CommandSource::kMouse:
      return "mouse";
    case CommandSource::kScript:
      return "script";
  }
  return "unknown";
}

std::optional<CommandKind> CommandFromViewerButtons(bool left, bool right) {
  if (!left && right) return CommandKind::kFreeze;
  if (left && !right) return CommandKind::kRange;
  if (left && right) return CommandKind::kUnfreeze;
  return std::nullopt;
}

std::optional<CommandKind> CommandFromVoice(devices::VoiceCommand voice) {
  switch (voice) {
    case devices::VOICE_FREEZE:
      return CommandKind::kFreeze;
    case devices::VOICE_RANGE:
      return CommandKind::kRange;
    case devices::VOICE_UNFREEZE:
      return CommandKind::kUnfreeze;
    case devices::VOICE_BOX:
      return CommandKind::kIdentifyBox;
    case devices::VOICE_CYLINDER:
      return CommandKind::kIdentifyCylinder;
    case devices::VOICE_MARK:
      return CommandKind::kMark;
    case devices::VOICE_UNMARK:
      return CommandKind::kUnmark;
    case devices::VOICE_REMOVE_POINTS:
      return CommandKind::kRemovePoints;
    case devices::VOICE_WIREFRAME:
      return CommandKind::kWireframe;
    case devices::VOICE_SOLID:
      return CommandKind::kSolid;
    case devices::VOICE_REMOVE_MODEL:
      return CommandKind::kRemoveModel;
    default:
      return std::nullopt;
  }
}

std::optional<CommandKind> CommandFromJoystickButton(int button) {
  switch (button) {
    case 1:
      return CommandKind::kUnmark;
    case 2:
      return CommandKind::kToggleWireframe;
    case 3:
      return CommandKind::kRemoveModel;
    default:
      return std::nullopt;
  }
}

}  // namespace igms::control
