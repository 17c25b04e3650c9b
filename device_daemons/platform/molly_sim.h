// A simulated MOLLY camera platform (molly_protocol.h) with the faults of a real one
// (Cooke, Interactive Graphical Model Building using Virtual Reality, section 4.4):
//
// - finite speed and acceleration: each axis follows a trapezoidal profile towards its
//   target at the servo rate; "steps per move" sets the move's nominal duration
//   (steps / servo_hz seconds), never faster than the axis's maximum speed;
// - mechanical limits: a target beyond them is clamped, so the platform may not reach
//   what it was told (the ORIENTATION reply carries the limit flag);
// - encoder quantisation: the reported orientation is the motor position rounded to whole
//   ticks (3.684e-3 degrees yaw, 1.750e-2 degrees pitch and roll);
// - optional gear backlash on pitch and roll: the camera follows the motor only once the
//   motor has taken up the play (a dead band `backlash_deg` wide), so a 0 -> 20 -> 0 degree
//   tilt brings the camera back off by backlash_deg while the encoders read 0. The thesis
//   measured 1.59 degrees. The encoders cannot see it; TrueDegrees() can.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "device_daemons/platform/molly_protocol.h"
#include "device_daemons/serial/pty_host.h"

namespace igms::devices {

struct MollySimOptions {
  double servo_hz = 200;
  std::array<double, 3> max_speed_deg_s{90, 60, 60};  // yaw, pitch, roll
  std::array<double, 3> max_accel_deg_s2{360, 240, 240};
  std::array<double, 3> limit_deg{170, 60, 30};  // +- from zero
  double backlash_deg = 0;                       // pitch and roll
  uint32_t steps_per_move = 1;                   // at power-up: full speed
  bool Check(std::string* error) const;
};

class MollySim : public SimulatedDevice {
 public:
  explicit MollySim(MollySimOptions options = {});

  std::vector<std::string> OnInput(std::string_view bytes, int64_t now_ns) override;
  std::vector<std::string> Poll(int64_t now_ns, int64_t* next_wake_ns) override;

  // Advances the dynamics to now_ns (also done by Poll and OnInput).
  void AdvanceTo(int64_t now_ns);
  molly::Ticks Encoders() const;
  bool Moving() const;
  // The camera's actual orientation (yaw, pitch, roll), backlash included, in degrees.
  std::array<double, 3> TrueDegrees() const;
  uint64_t commands() const { return commands_; }

 private:
  void Step(double dt);
  void SetTarget(const molly::Ticks& ticks);
  double DegPerTick(int axis) const;

  MollySimOptions options_;
  Frame7Parser parser_{molly::BodyLength};
  std::array<double, 3> motor_deg_{};  // motor side, in output degrees
  std::array<double, 3> velocity_{};
  std::array<double, 3> target_deg_{};
  std::array<double, 3> move_speed_{};
  std::array<double, 3> output_deg_{};  // camera side (backlash)
  bool at_limit_ = false;
  int64_t last_ns_ = -1;
  uint64_t commands_ = 0;
};

}  // namespace igms::devices
