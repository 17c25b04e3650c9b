#include "common/calibration/thesis_calibration.h"

#include <stdexcept>
#include <string>

namespace igms::calibration {

const StereoCalibration& ThesisCalibration() {
  static const StereoCalibration calibration = [] {
    std::string error;
    auto parsed = ParseCalibration(std::string(ThesisCalibrationYaml()), &error);
    // The file is checked in and tested: failing here is a broken build, not bad input.
    if (!parsed) throw std::logic_error("built-in thesis_calibration.yaml: " + error);
    return *parsed;
  }();
  return calibration;
}

}  // namespace igms::calibration
