// The thesis's calibration file as the lab ships it (equations 4.1, 4.2, a nominal platform
// and ranger), loaded from the repository for the control tests.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "common/calibration/calibration_file.h"

namespace igms::control::testing {

inline calibration::StereoCalibration ThesisCalibration() {
  const char* dir = std::getenv("IGMS_SOURCE_DIR");
  const std::string path =
      std::string(dir ? dir : ".") + "/common/calibration/data/thesis_calibration.yaml";
  auto c = calibration::LoadCalibration(path);
  if (!c.ok()) ADD_FAILURE() << c.error();
  return c.ok() ? *c : calibration::StereoCalibration{};
}

}  // namespace igms::control::testing
