// A simulated UDM-FL ranger (udm_protocol.h): on each 'R' it measures the scene
// (ranger_scene.h) from its current pose, which follows the camera platform, and answers
// after the measurement time (udm::kMeasureNs: at most 6 ranges a second; requests while
// measuring are ignored), with Gaussian noise of noise_fraction of the range. An injected fixed range
// overrides the scene.
#pragma once

#include <optional>
#include <random>

#include "device_daemons/ranger/ranger_scene.h"
#include "device_daemons/ranger/udm_protocol.h"
#include "device_daemons/serial/pty_host.h"

namespace igms::devices {

struct RangerSimOptions {
  RangerScene scene = RangerScene::Testbed();
  double noise_fraction = 0.002;
  uint32_t seed = 7;
};

class RangerSim : public SimulatedDevice {
 public:
  explicit RangerSim(RangerSimOptions options = {});
  std::vector<std::string> OnInput(std::string_view bytes, int64_t now_ns) override;
  std::vector<std::string> Poll(int64_t now_ns, int64_t* next_wake_ns) override;

  void SetPose(const RangerPose& pose) { pose_ = pose; }
  // A fixed answer: a range in inches, or no echo (nullopt inside). Clear with Release().
  void Override(std::optional<double> range_in) { override_ = range_in; }
  void Release() { override_.reset(); }
  // What the sensor would read now, without noise.
  std::optional<double> TrueRange() const;

 private:
  RangerSimOptions options_;
  RangerPose pose_;
  std::optional<std::optional<double>> override_;
  int64_t answer_at_ns_ = -1;
  std::mt19937 rng_;
};

}  // namespace igms::devices
