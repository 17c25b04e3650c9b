// Scripted operator sessions: a YAML list of what the operator's head, hands and voice do
// (docs/scripts.md). igms-control --script FILE plays one with no display; every action
// goes in through a device simulator's SimService.Inject, so it takes the real serial path,
// and the player waits until the session shows the action's effect.
//
//   - look: {yaw: 12.5, pitch: 0, roll: 0}  # the viewer's head pose, degrees
//   - button: freeze                         # viewer buttons: freeze (01), range (10),
//                                            # unfreeze (11), or the two digits
//   - move_to: [4.2, -1.0, 61.3]             # the stick, closed loop, until the pointer is
//                                            # within 0.02 (or {point: [...], tolerance: T})
//   - trigger                                # the FlyBox trigger: a mark
//   - stick: {x: 0, y: 0.5, twist: 0, seconds: 0.4}
//   - joystick_button: 1                     # FlyBox buttons 1-8 (table 2.2)
//   - range                                  # viewer buttons 10
//   - say: cylinder                          # a phrase the voice daemon hears
//   - fault: {device: joystick, garbage_bytes: 40}
//   - wait_for: {mode: model_building, timeout: 20}   # (or "model building") or marks: N, models:
//   N,
//                                                     # peer_up: NAME, peer_down: NAME
//   - screenshot: overlay.png                # the window's next frame as a PNG file beside the
//                                            # script (offscreen without a display; skipped
//                                            # with --no-window)
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "igms/devices.pb.h"

namespace igms::control {

enum class ActionKind {
  kLook,
  kButton,
  kMoveTo,
  kTrigger,
  kStick,
  kJoystickButton,
  kRange,
  kSay,
  kFault,
  kWaitFor,
  kScreenshot,
};

struct ScriptAction {
  ActionKind kind = ActionKind::kLook;
  int line = 0;      // in the script file, from 1
  std::string text;  // the action as written, for messages
  double timeout_s = 30;

  double yaw = 0, pitch = 0, roll = 0;              // look
  bool left = false, right = false;                 // button
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // move_to
  double tolerance = 0.02;                          // move_to, world units
  double x = 0, y = 0, twist = 0, seconds = 0;      // stick
  int joystick_button = 0;                          // 1-8
  std::string phrase;                               // say
  std::string device;                               // fault
  devices::SimFault fault;
  // wait_for: exactly one of these.
  std::string mode, peer_up, peer_down;
  std::optional<int> marks, models;
  std::string file;  // screenshot
};

struct Script {
  std::string source;
  std::vector<ScriptAction> actions;
};

// Parses a script; an unknown action or a bad value is an error naming source:line.
Result<Script> ParseScript(const std::string& text, const std::string& source);
Result<Script> LoadScript(const std::string& path);

std::string_view ActionName(ActionKind kind);

}  // namespace igms::control
