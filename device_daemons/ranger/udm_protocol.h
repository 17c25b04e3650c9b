// The ultrasonic ranger's serial protocol. The Contaq UDM-FL ranged 2 in to 60 ft at up to
// 6 Hz with a 12-degree beam, polled on the operator's request (Cooke, Interactive
// Graphical Model Building using Virtual Reality, section 2.1.5); its byte layout does not
// survive, so this one is ours, on Frame7 (device_daemons/serial/frame7.h), written down
// in docs/devices.md.
//
//   host -> ranger   'R': measure once. The ranger answers after its measurement time
//                    (at most 6 a second).
//   ranger -> host   0x88 RANGE    body 3: range, unsigned 21 bits, in 0.01 in    5 bytes
//                    0x89 NO_ECHO  body 0: nothing inside 2 in .. 60 ft           2 bytes
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "device_daemons/serial/frame7.h"

namespace igms::devices::udm {

inline constexpr char kMeasure = 'R';
inline constexpr uint8_t kRange = 0x88;
inline constexpr uint8_t kNoEcho = 0x89;
inline constexpr double kMinRangeIn = 2.0;
inline constexpr double kMaxRangeIn = 720.0;
inline constexpr double kStepIn = 0.01;
inline constexpr double kMaxRateHz = 6.0;
inline constexpr double kBeamWidthDeg = 12.0;
// Measurement time: a request answered back to back yields 6 ranges a second, the answer's
// five bytes on a 9600-baud line included.
inline constexpr int64_t kMeasureNs = 1'000'000'000 / 6 - 5 * 1'041'667;

int BodyLength(uint8_t head);
// A range outside 2 in .. 60 ft (or not finite) encodes as NO_ECHO.
std::string EncodeRange(std::optional<double> range_in);
// nullopt: not a ranger frame. Otherwise the range, or an empty optional for no echo.
std::optional<std::optional<double>> Decode(const Frame7& frame);

}  // namespace igms::devices::udm
