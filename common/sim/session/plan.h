// The planner of a simulated modelling session: for every cylinder and box of the simulated
// site, what an operator does to model it (Cooke, *Interactive Graphical Model Building using
// Virtual Reality* (1993), sections 2.4 and 4.3): look at it so the platform pans to it,
// freeze, move the 3D pointer to each of the four marks the operator mark model gives for
// the left camera at that pose (common/sim/marks.h), mark each, range, and say its type.
// The result is a script for igms-control --script (docs/scripts.md). Only the simulation
// knows the truth; the control client that plays the script never sees it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/geometry/platform.h"
#include "common/sim/marks.h"
#include "common/sim/scene.h"

namespace igms::site {

struct PlanOptions {
  uint64_t mark_seed = 1;  // object i's marks use mark_seed * 1000 + i, as igms-vision-demo's
  MarkModel marks;
  bool pan = true;  // turn the head (and the platform) to centre each object
  double max_pan_deg = 20;
  bool range = true;  // range once the marks are in
  double move_timeout_s = 60;
  // A screenshot of the overlay once each object is modelled (or not found), named
  // overlay-NN-NAME.png beside the script (igms-control's window, offscreen without a display).
  bool screenshots = true;
  std::vector<std::string> only;  // plan just these objects (by name); empty: all
};

struct PlannedObject {
  size_t index = 0;  // in the scene
  std::string name;
  bool box = false;
  double yaw_deg = 0;  // the head's yaw, which the platform's pan follows
  Marks marks;         // world units, for the left camera at that pose
};

// Every cylinder and box, in the scene's order. An object that cannot be marked from any
// pan (not wholly in front of the left camera) is an error naming it.
Result<std::vector<PlannedObject>> PlanSession(
    const Scene& scene, const std::optional<geometry::PlatformModel>& platform,
    const PlanOptions& options = {});

// The script that carries the plan out; `origin` names the scene in its comment.
std::string PlanScript(const std::vector<PlannedObject>& plan, const std::string& origin,
                       const PlanOptions& options = {});

}  // namespace igms::site
