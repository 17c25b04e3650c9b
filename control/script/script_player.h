// Plays a script (script.h) against a running control client: each action is injected into
// a device simulator's SimService, so it takes the real serial path to its daemon and on to
// the session, and the player waits until the session's view shows the action's effect. A
// timeout names the script's line and what was awaited.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>

#include "common/base/result.h"
#include "control/app/control_app.h"
#include "control/script/script.h"

namespace igms::control {

struct ScriptPlayerOptions {
  std::map<Peer, PeerAddress> devices;  // the device daemons (their SimService)
  std::string token;
  // move_to: full deflection at this distance (world units); smaller errors deflect the
  // stick in proportion, but never below `min_deflection` (the session's dead band).
  double full_deflection_at = 1.0;
  double min_deflection = 0.08;
  // screenshot: writes the window's next frame to the file (igms-control resolves a relative
  // name against the script's folder); unset: the action is logged and skipped (no window).
  std::function<Result<bool>(const std::string& file)> screenshot;
};

class ScriptPlayer {
 public:
  ScriptPlayer(ControlApp& app, ScriptPlayerOptions options);
  ~ScriptPlayer();

  // Plays every action in order. The first that fails stops the script: its error names
  // the file and line. Returns how many actions were played.
  Result<int> Play(const Script& script);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace igms::control
