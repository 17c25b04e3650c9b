#include "device_daemons/joystick/flybox_sim.h"

#include <algorithm>

namespace igms::devices {

void FlyBoxSim::Set(const JoystickState& s) {
  state_.analog = {s.x(), s.y(), s.twist(), s.lever0(), s.lever1(), 0, 0, 0};
  state_.digital = (s.buttons() & 0xFF) | (s.trigger() ? 1U << cerealbox::kTriggerBit : 0U);
}

std::string FlyBoxSim::Report() {
  ++reports_;
  return cerealbox::EncodeReport(layout_, state_);
}

std::vector<std::string> FlyBoxSim::OnInput(std::string_view bytes, int64_t now_ns) {
  std::vector<std::string> out;
  for (char c : bytes) {
    if (in_config_) {
      if (c != '\n') {
        if (pending_config_.size() < 16) pending_config_.push_back(c);
        continue;
      }
      in_config_ = false;
      cerealbox::Layout layout;
      if (cerealbox::ParseConfig(pending_config_, &layout)) {
        layout_ = layout;
        out.emplace_back("a\n");
      }  // a malformed configuration gets no acknowledgement, as on the box
      continue;
    }
    switch (c) {
      case 'T':
        continuous_ = false;
        out.push_back(cerealbox::IdentString('F'));
        break;
      case 'c':
      case 's':
        continuous_ = false;
        in_config_ = true;
        config_command_ = c;
        pending_config_.clear();
        break;
      case 'p':
      case 'o':
        continuous_ = false;
        out.push_back(Report());
        break;
      case 'C':
        continuous_ = true;
        next_report_ns_ = now_ns;
        break;
      case 'h':
        continuous_ = false;
        out.emplace_back("a\n");
        break;
      default:
        break;  // not a command (e.g. the 'E' some drivers send after 'p')
    }
  }
  return out;
}

std::vector<std::string> FlyBoxSim::Poll(int64_t now_ns, int64_t* next_wake_ns) {
  std::vector<std::string> out;
  if (!continuous_) return out;
  const auto period = static_cast<int64_t>(1e9 / kMaxRateHz);
  if (now_ns >= next_report_ns_) {
    out.push_back(Report());
    next_report_ns_ += period;
    if (next_report_ns_ < now_ns) next_report_ns_ = now_ns + period;
  }
  *next_wake_ns = std::min(*next_wake_ns, next_report_ns_);
  return out;
}

}  // namespace igms::devices
