#include "device_daemons/platform/molly_sim.h"

#include <algorithm>
#include <cmath>

namespace igms::devices {

bool MollySimOptions::Check(std::string* error) const {
  for (int a = 0; a < 3; ++a) {
    if (!(max_speed_deg_s[a] > 0) || !(max_accel_deg_s2[a] > 0) || !(limit_deg[a] > 0)) {
      *error = "platform simulator: speeds, accelerations and limits must be positive";
      return false;
    }
  }
  if (!(servo_hz > 0) || !(backlash_deg >= 0) || steps_per_move == 0) {
    *error = "platform simulator: servo rate and steps per move must be positive, backlash >= 0";
    return false;
  }
  return true;
}

MollySim::MollySim(MollySimOptions options) : options_(options) {
  move_speed_ = options_.max_speed_deg_s;
  // The gears rest against the lower side of their play, as after homing from below.
  for (int a = 1; a < 3; ++a) output_deg_[a] = -options_.backlash_deg / 2;
}

double MollySim::DegPerTick(int axis) const {
  return axis == 0 ? molly::kYawDegPerTick : molly::kPitchRollDegPerTick;
}

void MollySim::SetTarget(const molly::Ticks& t) {
  const std::array<int32_t, 3> ticks{t.yaw, t.pitch, t.roll};
  const double duration = options_.steps_per_move / options_.servo_hz;
  at_limit_ = false;
  for (int a = 0; a < 3; ++a) {
    double target = ticks[a] * DegPerTick(a);
    if (std::abs(target) > options_.limit_deg[a]) {
      target = std::copysign(options_.limit_deg[a], target);
      at_limit_ = true;
    }
    target_deg_[a] = target;
    move_speed_[a] =
        std::min(options_.max_speed_deg_s[a], std::abs(target - motor_deg_[a]) / duration);
    move_speed_[a] = std::max(move_speed_[a], 1e-3);
  }
}

void MollySim::Step(double dt) {
  for (int a = 0; a < 3; ++a) {
    const double error = target_deg_[a] - motor_deg_[a];
    const double accel = options_.max_accel_deg_s2[a];
    // Fastest speed from which the axis can still stop at the target.
    const double v_stop = std::sqrt(2 * accel * std::abs(error));
    const double v_want = std::copysign(std::min(move_speed_[a], v_stop), error);
    const double dv = std::clamp(v_want - velocity_[a], -accel * dt, accel * dt);
    velocity_[a] += dv;
    double next = motor_deg_[a] + velocity_[a] * dt;
    if ((error > 0 && next > target_deg_[a]) || (error < 0 && next < target_deg_[a]) ||
        (std::abs(error) < 0.5 * DegPerTick(a) && std::abs(velocity_[a]) < accel * dt)) {
      next = target_deg_[a];
      velocity_[a] = 0;
    }
    motor_deg_[a] = next;
    if (a == 0) {
      output_deg_[a] = motor_deg_[a];
    } else {
      const double half = options_.backlash_deg / 2;
      output_deg_[a] = std::clamp(output_deg_[a], motor_deg_[a] - half, motor_deg_[a] + half);
    }
  }
}

void MollySim::AdvanceTo(int64_t now_ns) {
  if (last_ns_ < 0) last_ns_ = now_ns;
  const double dt = 1.0 / options_.servo_hz;
  const auto step_ns = static_cast<int64_t>(dt * 1e9);
  while (now_ns - last_ns_ >= step_ns) {
    Step(dt);
    last_ns_ += step_ns;
  }
}

molly::Ticks MollySim::Encoders() const {
  const auto q = [this](int a) {
    return static_cast<int32_t>(std::lround(motor_deg_[a] / DegPerTick(a)));
  };
  return {q(0), q(1), q(2)};
}

bool MollySim::Moving() const {
  for (int a = 0; a < 3; ++a) {
    if (velocity_[a] != 0 || motor_deg_[a] != target_deg_[a]) return true;
  }
  return false;
}

std::array<double, 3> MollySim::TrueDegrees() const { return output_deg_; }

std::vector<std::string> MollySim::OnInput(std::string_view bytes, int64_t now_ns) {
  AdvanceTo(now_ns);
  std::vector<std::string> out;
  for (char c : bytes) {
    if (parser_.Feed(static_cast<uint8_t>(c)) != ParseResult::kGood) continue;
    const auto m = molly::Decode(parser_.frame());
    if (!m) continue;
    ++commands_;
    switch (m->head) {
      case molly::kSet:
        SetTarget(m->ticks);
        out.push_back(molly::EncodeAck(molly::kSet));
        break;
      case molly::kSpeed:
        options_.steps_per_move = m->steps_per_move;
        out.push_back(molly::EncodeAck(molly::kSpeed));
        break;
      case molly::kQuery:
        out.push_back(molly::EncodeOrientation(Encoders(), Moving(), at_limit_));
        break;
      case molly::kZero:
        for (int a = 0; a < 3; ++a) {
          output_deg_[a] -= motor_deg_[a];
          target_deg_[a] -= motor_deg_[a];
          motor_deg_[a] = 0;
        }
        out.push_back(molly::EncodeAck(molly::kZero));
        break;
      default:
        break;  // the platform's own replies echoed back: ignored
    }
  }
  return out;
}

std::vector<std::string> MollySim::Poll(int64_t now_ns, int64_t* next_wake_ns) {
  AdvanceTo(now_ns);
  if (Moving())
    *next_wake_ns = std::min(*next_wake_ns, now_ns + static_cast<int64_t>(1e9 / options_.servo_hz));
  return {};
}

}  // namespace igms::devices
