// Feeds arbitrary bytes, in arbitrary chunks, to the Linux joystick event decoder with a
// mapping taken from the input: nothing may crash, hang or overrun, and the state stays
// inside the FlyBox's ranges.
#include <cstddef>
#include <cstdint>

#include "device_daemons/joystick/gamepad.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace igms::devices;
  if (size < 2) return 0;
  GamepadMapping mapping;
  mapping.axes[data[0] % 5] = data[1] % 8;
  mapping.invert[data[1] % 5] = data[0] & 1;
  std::string error;
  if (!mapping.Check(&error)) return 0;
  GamepadDecoder decoder(mapping);
  size_t i = 2;
  while (i < size) {
    const size_t chunk = 1 + data[i] % 13;
    const size_t n = chunk < size - i ? chunk : size - i;
    decoder.Feed(data + i, n);
    i += n;
    const auto& s = decoder.state();
    for (double v : {s.x(), s.y(), s.twist(), s.lever0(), s.lever1()}) {
      if (!(v >= -1.0 && v <= 1.0)) __builtin_trap();
    }
    if (s.buttons() > 0xFF) __builtin_trap();
  }
  return 0;
}
