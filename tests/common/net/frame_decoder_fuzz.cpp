// libFuzzer target: any byte stream through the frame decoder and envelope parser, in any
// split, must decode, ask for more, or fail cleanly.
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/net/framing.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace igms::net;
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  const std::size_t limit = size > 0 ? 16 + data[0] * 64 : 16;
  while (!rest.empty()) {
    DecodeResult r = DecodeFrame(rest, limit);
    if (r.status != DecodeStatus::kFrame) break;
    if (r.consumed == 0 || r.consumed > rest.size()) __builtin_trap();
    igms::Envelope e;
    std::string error;
    igms::Envelope head;
    std::string_view payload;
    const bool viewed = ParseEnvelopeView(r.frame, &head, &payload, &error);
    // A payload view, when there is one, lies inside its frame.
    if (viewed && !payload.empty() &&
        (payload.data() < r.frame.data() ||
         payload.data() + payload.size() > r.frame.data() + r.frame.size())) {
      __builtin_trap();
    }
    const bool parsed = ParseEnvelope(r.frame, &e, &error);
    // Both parsers accept and refuse the same frames, and agree on the payload.
    if (viewed != parsed) __builtin_trap();
    if (parsed && e.payload() != payload) __builtin_trap();
    if (parsed) {
      // What parsed must frame again and decode to the same bytes.
      const std::string again = EncodeFrame(e);
      DecodeResult r2 = DecodeFrame(again, again.size());
      if (r2.status != DecodeStatus::kFrame || r2.consumed != again.size()) __builtin_trap();
    }
    rest.remove_prefix(r.consumed);
  }
  return 0;
}
