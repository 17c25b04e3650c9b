// The window's keyboard and mouse as a stand-in for the thesis's devices: each key is one of
// the session's commands (control/session/commands.h), the same a viewer button, a FlyBox
// button or a spoken word gives, so a session runs whole without the old hardware. The key
// map is in docs/window.md and on the help overlay (KeyHelp in view_from_session.h).
#pragma once

#include <Eigen/Core>

#include "control/session/commands.h"

namespace igms::control {

enum class WindowAction {
  kNone,
  kCommand,     // a session command
  kQuit,        // end the session
  kToggleHelp,  // the help overlay
  kScreenshot,  // a PNG of the window
  kNextStereo,  // the next stereo mode
  kOffset,      // move the video against the graphics (VideoService.SetOverlay)
};

struct KeyAction {
  WindowAction action = WindowAction::kNone;
  CommandKind command = CommandKind::kFreeze;
  Eigen::Vector2i offset = Eigen::Vector2i::Zero();  // pixels, u right, v down
  CommandSource source = CommandSource::kKeyboard;
};

// A key pressed (GLFW's key codes and modifier bits).
KeyAction MapKey(int key, int mods);
// A mouse button pressed: left marks, right unmarks.
KeyAction MapMouseButton(int button);

// The pointer's drive from the keys held: I/K up/down, J/L left/right, PgUp/PgDn farther and
// nearer; Shift drives at a quarter. `held(key)` says whether a key is down.
template <typename Held>
PointerDrive DriveFromKeys(Held held, bool slow, int64_t time_ns);

// Keys the drive reads (GLFW codes), in the order right, left, up, down, far, near.
extern const int kDriveKeys[6];

template <typename Held>
PointerDrive DriveFromKeys(Held held, bool slow, int64_t time_ns) {
  const double s = slow ? 0.25 : 1.0;
  PointerDrive d;
  d.right = s * ((held(kDriveKeys[0]) ? 1 : 0) - (held(kDriveKeys[1]) ? 1 : 0));
  d.up = s * ((held(kDriveKeys[2]) ? 1 : 0) - (held(kDriveKeys[3]) ? 1 : 0));
  d.forward = s * ((held(kDriveKeys[4]) ? 1 : 0) - (held(kDriveKeys[5]) ? 1 : 0));
  d.time_ns = time_ns;
  return d;
}

}  // namespace igms::control
