#include "control/session/inputs.h"

#include <cmath>

namespace igms::control {

int64_t StampTimeNs(const devices::Stamp& stamp) {
  if (stamp.device_time_us() != 0) return static_cast<int64_t>(stamp.device_time_us()) * 1000;
  return stamp.receive_monotonic_ns();
}

std::optional<CommandKind> ViewerButtonFilter::Feed(bool left, bool right, int64_t time_ns) {
  const int combination = (left ? 2 : 0) | (right ? 1 : 0);
  if (!have_ || combination != combination_ || time_ns < since_ns_) {
    have_ = true;
    combination_ = combination;
    since_ns_ = time_ns;
    acted_ = false;
  }
  if (acted_ || time_ns - since_ns_ < hold_ns_) return std::nullopt;
  acted_ = true;
  return CommandFromViewerButtons(left, right);
}

void ViewerButtonFilter::Reset() {
  have_ = false;
  acted_ = false;
}

JoystickInput JoystickMapper::Feed(const devices::JoystickState& reading) {
  JoystickInput out;
  auto axis = [&](double v) { return std::isfinite(v) && std::abs(v) >= dead_band_ ? v : 0.0; };
  out.drive.right = axis(reading.y());
  out.drive.up = axis(reading.twist());
  out.drive.forward = axis(reading.x());
  out.drive.time_ns = StampTimeNs(reading.stamp());
  if (have_) {
    if (reading.trigger() && !trigger_) out.commands.push_back(kJoystickTriggerCommand);
    const uint32_t pressed = reading.buttons() & ~buttons_;
    for (int b = 1; b <= 8; ++b) {
      if (!(pressed & (1u << (b - 1)))) continue;
      if (auto c = CommandFromJoystickButton(b)) out.commands.push_back(*c);
    }
  }
  have_ = true;
  buttons_ = reading.buttons();
  trigger_ = reading.trigger();
  return out;
}

void VoiceFilter::Subscribed(uint64_t newest_sequence) {
  subscribed_ = true;
  last_sequence_ = newest_sequence;
}

std::optional<CommandKind> VoiceFilter::Feed(const devices::VoiceState& reading) {
  if (!subscribed_) return std::nullopt;
  const uint64_t sequence = reading.stamp().sequence();
  if (sequence <= last_sequence_) return std::nullopt;
  last_sequence_ = sequence;
  return CommandFromVoice(reading.command());
}

}  // namespace igms::control
