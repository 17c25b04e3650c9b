#include "device_daemons/ranger/ranger_sim.h"

#include <algorithm>
#include <string>

namespace igms::devices {

RangerSim::RangerSim(RangerSimOptions options)
    : options_(std::move(options)), rng_(options_.seed) {}

std::optional<double> RangerSim::TrueRange() const {
  if (override_) return *override_;
  if (!options_.world.range) return std::nullopt;
  return options_.world.range(Beam(), udm::kBeamWidthDeg);
}

std::vector<std::string> RangerSim::OnInput(std::string_view bytes, int64_t now_ns) {
  for (char c : bytes) {
    if (c == udm::kMeasure && answer_at_ns_ < 0) answer_at_ns_ = now_ns + udm::kMeasureNs;
  }
  return {};
}

std::vector<std::string> RangerSim::Poll(int64_t now_ns, int64_t* next_wake_ns) {
  if (answer_at_ns_ < 0) return {};
  if (now_ns < answer_at_ns_) {
    *next_wake_ns = std::min(*next_wake_ns, answer_at_ns_);
    return {};
  }
  answer_at_ns_ = -1;
  std::optional<double> range = TrueRange();
  if (range && !override_ && options_.noise_fraction > 0) {
    range = *range + std::normal_distribution<double>(0, options_.noise_fraction * *range)(rng_);
  }
  return {udm::EncodeRange(range)};
}

}  // namespace igms::devices
