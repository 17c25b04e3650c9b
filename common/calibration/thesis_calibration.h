// The thesis's stereo calibration (Cooke, *Interactive Graphical Model Building using Virtual
// Reality* (1993), section 4.2, equations 4.1 left and 4.2 right) with the lab's nominal
// platform and ranger. Its one home is data/thesis_calibration.yaml, the lab's calibration
// file; the build embeds that file here, so code (the simulated site's cameras, the thesis's
// reference figures) reads the same matrices without finding a file at run time.
#pragma once

#include <string_view>

#include "common/calibration/calibration_file.h"

namespace igms::calibration {

// data/thesis_calibration.yaml, parsed once. 512 x 480 images, no lens.
const StereoCalibration& ThesisCalibration();

// The text of data/thesis_calibration.yaml as built in.
std::string_view ThesisCalibrationYaml();

}  // namespace igms::calibration
