// igms-control's section of the lab file, processes.control (docs/configuration.md):
//
//   control:
//     program: igms-control    # no port: the operator starts it at the viewer
//     all_axes: false          # slave pan only (the thesis), or pan, tilt and roll
//     pointer_start_depth: 36  # world units in front of the left camera
//     pointer_speed: 6         # world units a second at full deflection
//     video: video             # the process entry of each peer (default: its own name)
//     stereo: side-by-side     # the window: side-by-side, anaglyph, quad-buffer, left, right
//
// and lab.calibration (required), lab.database, lab.token.
#pragma once

#include <string>

#include "common/base/result.h"
#include "common/config/keys.h"
#include "common/config/process_options.h"
#include "control/app/control_app.h"

namespace igms::control {

// The settings as the file and flags give them, before they become ControlAppOptions.
struct ControlConfig {
  SessionOptions session;
  int settle_timeout_ms = 3000;
  int call_timeout_ms = 2000;
  int grab_timeout_ms = 5000;
  int locate_timeout_ms = 30000;
  int steps_per_move = 0;
  std::string peer_names[8];            // by Peer; empty: the peer's own name
  std::string stereo = "side-by-side";  // the window's stereo mode (control/render/stereo.h)
  std::string export_dir;               // absolute; empty: no exports (docs/exports.md)
};

config::Keys ControlKeys(ControlConfig* config);

// The app's options: the peers' addresses from the lab file (a peer with no entry is left
// out, and the session reports it missing), the token and the timeouts.
Result<ControlAppOptions> MakeControlAppOptions(const config::ProcessOptions& process,
                                                const ControlConfig& config);

}  // namespace igms::control
