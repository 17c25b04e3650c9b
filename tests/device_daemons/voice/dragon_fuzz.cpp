// Feeds arbitrary bytes to both Dragon line parsers: nothing may crash, hang or overrun,
// and every report they accept re-encodes to the three bytes of its line.
#include <cstddef>
#include <cstdint>

#include "device_daemons/voice/dragon_protocol.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace igms::voice;
  dragon::ReportParser reports;
  dragon::HostParser host;
  for (size_t i = 0; i < size; ++i) {
    if (reports.Feed(data[i]) == igms::devices::ParseResult::kGood) {
      const auto& r = reports.report();
      const std::string line =
          r.command ? dragon::EncodeCommand(*r.command) : dragon::EncodeAlive();
      if (line.size() != 3) __builtin_trap();
    }
    if (host.Feed(data[i]) == igms::devices::ParseResult::kGood) {
      const auto& q = host.request();
      if (q.probe == q.state.has_value()) __builtin_trap();  // exactly one of them
    }
  }
  if (reports.good_frames() + reports.bad_frames() > size) __builtin_trap();
  return 0;
}
