#include "device_daemons/ranger/udm_protocol.h"

#include <cmath>

namespace igms::devices::udm {

int BodyLength(uint8_t head) {
  if (head == kRange) return 3;
  if (head == kNoEcho) return 0;
  return -1;
}

std::string EncodeRange(std::optional<double> range_in) {
  if (!range_in || !std::isfinite(*range_in) || *range_in < kMinRangeIn ||
      *range_in > kMaxRangeIn) {
    return EncodeFrame7(kNoEcho, "");
  }
  Frame7Writer w;
  w.PutUnsigned(static_cast<uint32_t>(std::lround(*range_in / kStepIn)), 21);
  return EncodeFrame7(kRange, w.Finish());
}

std::optional<std::optional<double>> Decode(const Frame7& f) {
  if (f.head == kNoEcho && f.body_size == 0) return std::optional<double>();
  if (f.head != kRange || f.body_size != 3) return std::nullopt;
  Frame7Reader r(f.body.data(), f.body_size);
  const double range = r.GetUnsigned(21) * kStepIn;
  if (range < kMinRangeIn || range > kMaxRangeIn) return std::nullopt;
  return std::optional<double>(range);
}

}  // namespace igms::devices::udm
