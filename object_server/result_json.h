// The JSON form of a locate result, as `igms locate --json` prints it (BRIEF contract):
//   cylinder: {"found": true, "type": "cylinder", "center": [x,y,z], "axis": [ax,ay,az],
//              "radius": r, "height": h, "sigma": {...}, ...}
//   box:      {"found": true, "type": "box", "min": [x,y,z], "max": [x,y,z], "center": [...],
//              "size": [...], "texture_rect": [u0, v0, u1, v1], "sigma": {...}, ...}
//   failure:  {"found": false, "type": ..., "reason": "<code>", "detail": "<for a person>"}
// Extra fields: "rms_px" [left, right], "outline_samples", "boundary_pixels", "ssd_rms",
// "elapsed_ms".
#pragma once

#include <string>

#include "object_server/locate.h"

namespace igms::object {

std::string ResultToJson(const LocateResult& result);

}  // namespace igms::object
