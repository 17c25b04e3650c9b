// The viewer's serial protocol. The Fakespace BOOM2C sent its pose "at 9600 baud using a
// compact protocol" at up to 70 Hz (Cooke, Interactive Graphical Model Building using
// Virtual Reality, section 2.1.3); that protocol's specification does not survive, so this
// one is ours, built on Frame7 (device_daemons/serial/frame7.h) and written down in
// docs/devices.md.
//
//   host -> viewer   'P' one report; 'S' report continuously at 70 Hz; 'X' stop reports.
//   viewer -> host   a 13-byte report (13.5 ms at 9600 baud, so 70 Hz fits):
//     head  = 0b11BBSSSS: B = the handle buttons (left = bit 5, right = bit 4),
//             S = a 4-bit report counter
//     body  = 11 bytes, 77 bits MSB first: x, y, z as signed 12-bit counts of 0.5 mm
//             (+-1.0235 m), yaw, pitch, roll as signed 13-bit counts of 360/8192 degrees
//             (0.044 degrees, finer than a camera pixel's 0.048), two zero bits
//     check = Frame7 checksum
//
// Positions and angles are relative to the power-up pose, as the BOOM's were.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "device_daemons/serial/frame7.h"

namespace igms::devices::boom {

inline constexpr int kReportBody = 11;
inline constexpr size_t kReportLength = kReportBody + 2;
inline constexpr double kMaxRateHz = 70.0;
inline constexpr double kPositionStepM = 0.0005;
inline constexpr double kAngleStepDeg = 360.0 / 8192.0;
inline constexpr char kPoll = 'P';
inline constexpr char kStream = 'S';
inline constexpr char kStop = 'X';

struct Pose {
  double x_m = 0, y_m = 0, z_m = 0;
  double yaw_deg = 0, pitch_deg = 0, roll_deg = 0;
  bool left = false, right = false;
  uint8_t counter = 0;  // 0..15
};

// Frame7 body length for a viewer head: 11 for 0xC0..0xFF, -1 otherwise.
int BodyLength(uint8_t head);

// Positions are clamped to the field's range; angles wrapped into [-180, 180).
std::string EncodeReport(const Pose& pose);
// From a frame the parser accepted (BodyLength's heads); nullopt for any other frame.
std::optional<Pose> DecodeReport(const Frame7& frame);

// Wraps degrees into [-180, 180).
double WrapDegrees(double deg);

}  // namespace igms::devices::boom
