// A Linux joystick or gamepad as a stand-in for the FlyBox: the kernel's joystick API
// (linux/joystick.h, Documentation/input/joydev) decoded into the same JoystickState the
// FlyBox path publishes. Pure: no I/O (gamepad_reader.h reads the device).
//
// The device delivers 8-byte struct js_event records: time (ms, the driver's clock), value
// (axes -32767..32767, buttons 0/1), type (JS_EVENT_AXIS, JS_EVENT_BUTTON, either or'ed
// with JS_EVENT_INIT for the state reported right after opening) and number (the axis or
// button). Axis values are scaled to [-1, 1].
//
// Mapping (GamepadMapping): which device axis drives each of the FlyBox's three axes and
// two levers (optionally inverted), which device buttons are buttons 1-8 and which is the
// trigger. The default suits the common Linux gamepad layout (xpad and most USB pads):
//   x (forward/backward) = -axis 1 (left stick, pushed away = forward = +1)
//   y (left/right)       =  axis 0 (left stick, right = +1)
//   twist                =  axis 3 (right stick, right = +1)
//   lever0, lever1       =  axes 2 and 5 (the analogue triggers)
//   trigger              =  button 0 (on a flight stick, its trigger)
//   buttons 1-8          =  buttons 1..8
// An index of -1 leaves that input unmapped (axes read 0, buttons released). Events for
// axes or buttons the mapping does not use are counted as ignored, not errors.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

#include "igms/devices.pb.h"

namespace igms::devices {

struct GamepadMapping {
  enum Axis { kX, kY, kTwist, kLever0, kLever1 };
  std::array<int, 5> axes = {1, 0, 3, 2, 5};
  std::array<bool, 5> invert = {true, false, false, false, false};
  std::array<int, 8> buttons = {1, 2, 3, 4, 5, 6, 7, 8};  // device button of FlyBox 1..8
  int trigger = 0;
  // Indices in -1..255 (js_event numbers are 8 bits); no device button used twice.
  bool Check(std::string* error) const;
};

inline constexpr size_t kJsEventSize = 8;

class GamepadDecoder {
 public:
  explicit GamepadDecoder(GamepadMapping mapping = {});

  // Feeds bytes from the device; whole records update the state, a partial one waits for
  // the rest. Returns how many records were applied.
  size_t Feed(const uint8_t* data, size_t size);
  // Forgets a partial record and the state (the device was reopened: its INIT events
  // report the state again).
  void Reset();

  // The state now (stamp unset).
  const JoystickState& state() const { return state_; }
  // The driver's time of the last event, in milliseconds (wraps at 2^32).
  uint32_t last_event_ms() const { return last_event_ms_; }
  uint64_t events() const { return events_; }
  uint64_t ignored() const { return ignored_; }  // unmapped inputs and unknown types

 private:
  void Apply(uint32_t time_ms, int16_t value, uint8_t type, uint8_t number);

  GamepadMapping mapping_;
  JoystickState state_;
  uint8_t partial_[kJsEventSize] = {};
  size_t partial_size_ = 0;
  uint32_t last_event_ms_ = 0;
  uint64_t events_ = 0;
  uint64_t ignored_ = 0;
};

// A js_event record as the kernel writes it (native byte order), for tests and tools.
std::string EncodeJsEvent(uint32_t time_ms, int16_t value, uint8_t type, uint8_t number);

}  // namespace igms::devices
