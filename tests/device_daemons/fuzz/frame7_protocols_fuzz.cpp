// Feeds arbitrary bytes to the Frame7 parser with each protocol's head table (viewer,
// platform) and decodes every frame it accepts: nothing may crash, hang or overrun.
#include <cstddef>
#include <cstdint>

#include "device_daemons/platform/molly_protocol.h"
#include "device_daemons/serial/frame7.h"
#include "device_daemons/viewer/boom_protocol.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace igms::devices;
  Frame7Parser viewer(boom::BodyLength);
  Frame7Parser platform(molly::BodyLength);
  for (size_t i = 0; i < size; ++i) {
    if (viewer.Feed(data[i]) == ParseResult::kGood) {
      if (auto pose = boom::DecodeReport(viewer.frame())) {
        // A decoded pose re-encodes to a frame of the same length.
        if (boom::EncodeReport(*pose).size() != boom::kReportLength) __builtin_trap();
      }
    }
    if (platform.Feed(data[i]) == ParseResult::kGood) {
      if (auto m = molly::Decode(platform.frame()); m && m->head == molly::kSet) {
        if (molly::EncodeSet(m->ticks).size() != 9) __builtin_trap();
      }
    }
  }
  return 0;
}
