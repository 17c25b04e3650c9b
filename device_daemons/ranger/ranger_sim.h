// A simulated UDM-FL ranger (udm_protocol.h): on each 'R' it ranges its world (ranger_site.h:
// the simulated site, in igms-rangerd) from its mount at the current platform pose, and answers
// after the measurement time (udm::kMeasureNs: at most 6 ranges a second; requests while measuring
// are ignored). Beam 12 degrees, 2 in to 60 ft (outside: no echo), as the thesis's table
// 2.3 and section 2.1.5 give them.
//
// Noise: the thesis states the beam's spread (table 2.3) but no accuracy, so the
// simulator adds Gaussian noise of noise_fraction of the range (default 0.2%: 0.1 in at
// 4 ft, 1.4 in at 60 ft), then the protocol's 0.01 in steps. An injected fixed range
// overrides the site, without noise.
#pragma once

#include <optional>
#include <random>
#include <vector>

#include "device_daemons/ranger/ranger_site.h"
#include "device_daemons/ranger/udm_protocol.h"
#include "device_daemons/serial/pty_host.h"

namespace igms::devices {

struct RangerSimOptions {
  // What the beam meets (LoadRangerWorld; the thesis's testbed is common/sim/ranger's
  // TestbedRangerWorld). The default ranges nothing: every answer is no echo.
  RangerWorld world;
  double noise_fraction = 0.002;
  uint32_t seed = 7;
};

class RangerSim : public SimulatedDevice {
 public:
  explicit RangerSim(RangerSimOptions options = {});
  std::vector<std::string> OnInput(std::string_view bytes, int64_t now_ns) override;
  std::vector<std::string> Poll(int64_t now_ns, int64_t* next_wake_ns) override;

  // The platform's joint angles in radians (RangerMount::BeamAt).
  void SetJointAngles(std::vector<double> q) { q_ = std::move(q); }
  // The platform's reached orientation, through the mount's platform model.
  void SetPlatform(const PlatformState& reading) { q_ = options_.world.mount.AnglesOf(reading); }
  // A fixed answer: a range in inches, or no echo (nullopt inside). Clear with Release().
  void Override(std::optional<double> range_in) { override_ = range_in; }
  void Release() { override_.reset(); }
  // The beam now, and what the sensor would read now without noise.
  RangerBeam Beam() const { return options_.world.mount.BeamAt(q_); }
  std::optional<double> TrueRange() const;

 private:
  RangerSimOptions options_;
  std::vector<double> q_;
  std::optional<std::optional<double>> override_;
  int64_t answer_at_ns_ = -1;
  std::mt19937 rng_;
};

}  // namespace igms::devices
