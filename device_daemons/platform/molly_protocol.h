// The camera platform's serial protocol. The Fakespace MOLLY took orientations, a speed as
// steps per move, orientation queries and a reset to zero over a 9600-baud line (Cooke,
// Interactive Graphical Model Building using Virtual Reality, sections 2.1.7 and 4.4); its
// byte layout does not survive, so this one is ours, on Frame7
// (device_daemons/serial/frame7.h), written down in docs/devices.md.
//
// Orientation is in encoder ticks: yaw 1800 ticks a quadrant through a 13.57 gear
// (3.684e-3 degrees a tick), pitch and roll 1000 ticks a quadrant through 5.14
// (1.750e-2 degrees a tick).
//
//   host -> platform
//     0x81 SET      body 7: yaw signed 21 bits, pitch signed 14, roll signed 14   9 bytes
//     0x82 SPEED    body 2: steps per move, unsigned 14 bits (1..16383)           4 bytes
//     0x83 QUERY    body 0                                                         2 bytes
//     0x84 ZERO     body 0: the current orientation becomes zero                   2 bytes
//   platform -> host
//     0xA0 | flags  ORIENTATION body 7 as SET; flags bit 0 = moving, bit 1 = an axis
//                   is held at its mechanical limit                                9 bytes
//     0x90 ACK      body 1: the acknowledged command's head minus 0x80             3 bytes
//
// The platform answers every QUERY with an ORIENTATION and every SET, SPEED and ZERO with
// an ACK once accepted (a SET is accepted, then moved to as far as the limits allow).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "device_daemons/serial/frame7.h"

namespace igms::devices::molly {

inline constexpr double kYawDegPerTick = 360.0 / (4 * 1800) / 13.57;
inline constexpr double kPitchRollDegPerTick = 360.0 / (4 * 1000) / 5.14;

inline constexpr uint8_t kSet = 0x81;
inline constexpr uint8_t kSpeed = 0x82;
inline constexpr uint8_t kQuery = 0x83;
inline constexpr uint8_t kZero = 0x84;
inline constexpr uint8_t kAck = 0x90;
inline constexpr uint8_t kOrientation = 0xA0;
inline constexpr uint8_t kFlagMoving = 0x01;
inline constexpr uint8_t kFlagLimit = 0x02;
inline constexpr int kYawBits = 21;
inline constexpr int kPitchRollBits = 14;
inline constexpr uint32_t kMaxStepsPerMove = 16383;

struct Ticks {
  int32_t yaw = 0, pitch = 0, roll = 0;
  bool operator==(const Ticks&) const = default;
};

struct Message {
  uint8_t head = 0;  // kSet, kSpeed, kQuery, kZero, kAck, or kOrientation (flags removed)
  Ticks ticks;       // kSet, kOrientation
  uint32_t steps_per_move = 0;  // kSpeed
  uint8_t acked = 0;            // kAck: the command's head
  bool moving = false;          // kOrientation
  bool at_limit = false;
};

// Frame7 body length for any head of this protocol, either direction; -1 otherwise.
int BodyLength(uint8_t head);

std::string EncodeSet(const Ticks& ticks);         // ticks clamped to their fields
std::string EncodeSpeed(uint32_t steps_per_move);  // clamped to 1..16383
std::string EncodeQuery();
std::string EncodeZero();
std::string EncodeOrientation(const Ticks& ticks, bool moving, bool at_limit);
std::string EncodeAck(uint8_t command_head);

std::optional<Message> Decode(const Frame7& frame);

inline double YawDeg(int32_t ticks) { return ticks * kYawDegPerTick; }
inline double PitchRollDeg(int32_t ticks) { return ticks * kPitchRollDegPerTick; }

}  // namespace igms::devices::molly
