// The one command vocabulary of the operator's session, and what each input source of the
// thesis means in it (Cooke, *Interactive Graphical Model Building using Virtual Reality*,
// table 2.1 for the viewer's buttons, table 2.2 for the FlyBox, table 2.4 and section 2.4
// for the voice commands).
//
// Every source (viewer buttons, joystick, voice, and later the window's keys and mouse)
// becomes a Command; the session's state machine (session.h) knows only Commands, so a new
// source plugs in without touching it. Continuous pointer motion is not a command: a source
// that moves the pointer gives a PointerDrive (a deflection, integrated by the session).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "igms/devices.pb.h"

namespace igms::control {

enum class CommandKind {
  kFreeze,            // hold the platform and grab (table 2.1 "01", table 2.4)
  kUnfreeze,          // slave the platform to the viewer again (table 2.1 "11", table 2.4)
  kRange,             // move the pointer to the ultrasonic range (table 2.1 "10", table 2.4)
  kMark,              // a mark at the pointer (table 2.2 trigger, section 2.4)
  kUnmark,            // remove the last mark (table 2.2 button 1, section 2.4)
  kRemovePoints,      // remove every mark (table 2.6 "Removing points")
  kIdentifyBox,       // the marked object is a box (table 2.4)
  kIdentifyCylinder,  // ... a cylinder (table 2.4)
  kWireframe,         // draw models as wireframes (section 2.4)
  kSolid,             // draw models solid
  kToggleWireframe,   // wireframe <-> solid (table 2.2 button 2)
  kRemoveModel,       // the model the pointer is inside, else the last added (table 2.2 button 3)
  kUndo,              // the last mark, model added or model removed
};

enum class CommandSource { kViewerButtons, kJoystick, kVoice, kKeyboard, kMouse, kScript };

struct Command {
  CommandKind kind = CommandKind::kFreeze;
  CommandSource source = CommandSource::kScript;
  int64_t time_ns = 0;  // when it was issued (the session's monotonic clock)
};

// Pointer motion from a source: each component is a deflection in [-1, 1] along the left
// camera's axes at the grab (right, up, forward into the scene), scaled by the configured
// speed. `time_ns` is the reading's stamp on its source's clock (differences only are used).
struct PointerDrive {
  double right = 0.0;
  double up = 0.0;
  double forward = 0.0;
  int64_t time_ns = 0;
};

// "freeze", "identify_box", ...; "viewer_buttons", "joystick", "voice", ...
std::string_view CommandName(CommandKind kind);
std::string_view SourceName(CommandSource source);

// Table 2.1: 00 none, 01 freeze, 10 range, 11 unfreeze; the left button is the first digit.
std::optional<CommandKind> CommandFromViewerButtons(bool left, bool right);

// Table 2.4 and its extensions (devices.proto's VoiceCommand); nullopt for UNSPECIFIED or a
// value outside the enum.
std::optional<CommandKind> CommandFromVoice(devices::VoiceCommand voice);

// Table 2.2: FlyBox buttons 1-8 (1-based) and the trigger. Button 1 removes the last mark,
// button 2 toggles wireframe/solid, button 3 removes a model, 4-8 do nothing; the trigger
// marks a point.
std::optional<CommandKind> CommandFromJoystickButton(int button);
inline constexpr CommandKind kJoystickTriggerCommand = CommandKind::kMark;

}  // namespace igms::control
