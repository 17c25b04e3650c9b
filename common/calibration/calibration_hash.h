// The calibration's identity: a SHA-256 of its parsed content, so that copies of one
// calibration on two workstations agree even when their YAML differs in spacing, comments,
// key order or the way a number is written (docs/calibration.md, "The calibration's hash").
//
// The hash is taken over a canonical text of the content, in a fixed order:
//   igms-calibration-hash 1
//   left.P 3 4 <12 numbers, row by row>
//   left.image_size <width> <height>
//   left.K 3 3 <9 numbers> | left.K none
//   left.dist <n> <n numbers>
//   right.* as left.*
//   ranger.origin <3 numbers> / ranger.axis <3 numbers, normalised as loaded> | ranger none
//   platform.world_from_base 4 4 <16 numbers> / platform.joints <n> /
//     platform.joints[i] <name length>:<name> <theta_offset> <d> <a> <alpha>
//       <radians_per_tick>                                               | platform none
// one item a line, numbers printed with "%.17g" (which reads back to the same double) and
// -0 written as 0. A change of this form changes the first line's number.
#pragma once

#include <string>
#include <string_view>

#include "common/calibration/calibration_file.h"

namespace igms::calibration {

// The canonical text above.
std::string CanonicalCalibrationText(const StereoCalibration& calibration);

// SHA-256 of CanonicalCalibrationText, 64 lower-case hex digits.
std::string CalibrationHash(const StereoCalibration& calibration);

// SHA-256 of any bytes, 64 lower-case hex digits (OpenSSL's libcrypto).
std::string Sha256Hex(std::string_view bytes);

}  // namespace igms::calibration
