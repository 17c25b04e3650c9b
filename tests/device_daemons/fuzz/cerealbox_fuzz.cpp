// Feeds arbitrary bytes to the CerealBox report parser (the first byte picks the layout),
// the configuration and identification parsers, and the FlyBox simulator's command
// interpreter: nothing may crash, hang or overrun.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "device_daemons/joystick/cerealbox_protocol.h"
#include "device_daemons/joystick/flybox_sim.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace igms::devices;
  if (size == 0) return 0;
  cerealbox::Layout layout;
  layout.analog_mask = data[0];
  layout.digital_banks = data[0] % 4;
  layout.encoder_mask = static_cast<uint8_t>(data[0] >> 3);
  cerealbox::ReportParser parser(layout);
  for (size_t i = 1; i < size; ++i) {
    if (parser.Feed(data[i]) == ParseResult::kGood &&
        parser.report().analog_count > cerealbox::kMaxAnalog) {
      __builtin_trap();
    }
  }
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  cerealbox::Layout parsed;
  if (size >= 8) cerealbox::ParseConfig(text.substr(0, 8), &parsed);
  char type;
  std::string version;
  if (size >= cerealbox::kIdentLength)
    cerealbox::ParseIdent(text.substr(0, cerealbox::kIdentLength), &type, &version);
  FlyBoxSim sim;
  sim.OnInput(text, 0);
  int64_t wake = INT64_MAX;
  sim.Poll(1'000'000'000, &wake);
  return 0;
}
