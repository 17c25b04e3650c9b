#include "common/calibration/thesis_calibration.h"

#include <stdexcept>
#include <string>

namespace igms::calibration {

const StereoCalibration& ThesisCalibration() {
  static const StereoCalibration calibration = [] {
    auto parsed = ParseCalibration(std::string(ThesisCalibrationYaml()));
    // The file is checked in and tested: failing here is a broken build, not bad input.
    if (!parsed.ok()) throw std::logic_error("built-in thesis_calibration.yaml: " + parsed.error());
    return *parsed;
  }();
  return calibration;
}

}  // namespace igms::calibration
