// `igms calibrate` (the igms-calibrate executable): calibration from the command line.
//
//   igms calibrate points [FILE | --left FILE [--right FILE]] [--method thesis|normalized]
//                         [--image-size 512x480] [--output cal.yaml] [--json]
//   igms calibrate chessboard --left L1.jpg ... --right R1.jpg ... [--board 9x6] [--square 1]
//                         [--procedure joint|fixed|opencv-sample] [--output cal.yaml] [--json]
//   igms calibrate decompose CAL.yaml [--json]
//   igms calibrate platform --calibration CAL.yaml --observations FILE [--estimate-scales]
//                         [--output out.yaml] [--json]
//   igms calibrate platform --synthetic [--noise 0.3] [--estimate-scales] [--json]
//
// Text reports go to stdout (one JSON object with --json); progress and errors to stderr.
// Exit status: 0 success, 2 bad input (bad flags, unreadable or malformed files, degenerate
// data), 1 an unexpected failure. File formats: docs/calibration.md.
#pragma once

#include <iosfwd>

namespace igms::calibration::cli {

int RunCalibrate(int argc, const char* const argv[], std::ostream& out, std::ostream& err);

}  // namespace igms::calibration::cli
