#include "control/session/session_options.h"

#include <cmath>

namespace igms::control {
namespace {

bool Fail(std::string* error, const std::string& why) {
  if (error) *error = why;
  return false;
}

}  // namespace

bool SessionOptions::Check(std::string* error) const {
  if (steps_per_move > 16383) return Fail(error, "steps_per_move: at most 16383");
  if (settle_readings < 1) return Fail(error, "settle_readings: at least 1");
  if (settle_timeout_ns <= 0) return Fail(error, "settle_timeout: must be positive");
  if (!std::isfinite(pointer_start_depth) || pointer_start_depth <= 0)
    return Fail(error, "pointer_start_depth: must be a positive number of world units");
  if (!std::isfinite(pointer_speed) || pointer_speed <= 0)
    return Fail(error, "pointer_speed: must be a positive number of world units a second");
  if (!std::isfinite(stick_dead_band) || stick_dead_band < 0 || stick_dead_band >= 1)
    return Fail(error, "stick_dead_band: must be in [0, 1)");
  if (max_drive_step_ns <= 0) return Fail(error, "max_drive_step: must be positive");
  if (!std::isfinite(world_units_per_inch) || world_units_per_inch <= 0)
    return Fail(error, "world_units_per_inch: must be positive");
  if (button_hold_ns < 0) return Fail(error, "button_hold: must not be negative");
  if (please_wait_after_ns < 0) return Fail(error, "please_wait_after: must not be negative");
  if (welcome_after_ns < 0) return Fail(error, "welcome_after: must not be negative");
  return true;
}

}  // namespace igms::control
