// The session's settings, with their defaults. World units are the calibration's (inches
// for the thesis's testbed); times are nanoseconds of the monotonic clock events carry.
#pragma once

#include <cstdint>
#include <string>

namespace igms::control {

struct SessionOptions {
  // Verification: slave pan only, as the thesis did, or pan, tilt and roll.
  bool all_axes = false;
  uint32_t steps_per_move = 0;  // SetOrientation's speed; 0 keeps the platform's

  // Freeze: the platform has stopped once this many readings in a row say it is not
  // moving after the last SetOrientation was acknowledged; after `settle_timeout_ns` the
  // session grabs anyway, saying so.
  int settle_readings = 2;
  int64_t settle_timeout_ns = 3'000'000'000;

  // Pointer (table 2.2, section 4.3): starts on the left camera's optical axis at this
  // depth; the stick moves it at `pointer_speed` world units a second at full deflection.
  // Gaps between readings count at most `max_drive_step_ns` (a stick that went silent
  // does not fling the pointer).
  double pointer_start_depth = 36.0;
  double pointer_speed = 6.0;
  double stick_dead_band = 0.05;
  int64_t max_drive_step_ns = 100'000'000;

  // Ranger: its ranges are in inches; world units per inch (1 for an inch calibration,
  // 0.0254 for metres).
  double world_units_per_inch = 1.0;

  // Input discipline and cues.
  int64_t button_hold_ns = 100'000'000;          // viewer buttons (table 2.1)
  int64_t please_wait_after_ns = 2'000'000'000;  // a Locate in flight this long: "Please wait."
  int64_t welcome_after_ns = 1'800'000'000;      // "Welcome" after the introduction music

  // Start: with a required peer missing, wait for it (--wait) instead of exiting 1.
  bool wait_for_peers = false;
  // The platform obeys one client at a time: take control from whichever holds it with
  // the first command (--take-control). Without it, a platform held by another client is
  // not commanded until that client lets go, and the operator is told who holds it.
  bool take_control = false;

  // False with `error` naming the setting when one is out of range.
  bool Check(std::string* error = nullptr) const;
};

}  // namespace igms::control
