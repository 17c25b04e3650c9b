#include "device_daemons/viewer/boom_protocol.h"

#include <algorithm>
#include <cmath>

namespace igms::devices::boom {

namespace {
constexpr int kPositionBits = 12;
constexpr int kAngleBits = 13;

int32_t Count(double value, double step) {
  if (!std::isfinite(value)) return 0;
  const double c = std::round(value / step);
  const double max = SignedFieldMax(31);
  return static_cast<int32_t>(std::clamp(c, -max, max));
}
}  // namespace

int BodyLength(uint8_t head) { return (head & 0xC0) == 0xC0 ? kReportBody : -1; }

double WrapDegrees(double deg) {
  if (!std::isfinite(deg)) return 0;
  double w = std::fmod(deg + 180.0, 360.0);
  if (w < 0) w += 360.0;
  return w - 180.0;
}

std::string EncodeReport(const Pose& pose) {
  Frame7Writer w;
  for (double p : {pose.x_m, pose.y_m, pose.z_m})
    w.PutSigned(Count(p, kPositionStepM), kPositionBits);
  for (double a : {pose.yaw_deg, pose.pitch_deg, pose.roll_deg}) {
    int32_t c = Count(WrapDegrees(a), kAngleStepDeg);
    if (c == 4096) c = -4096;  // +180 rounds up to the wrap
    w.PutSigned(c, kAngleBits);
  }
  w.PutUnsigned(0, 2);
  const auto head = static_cast<uint8_t>(0xC0 | (pose.left ? 0x20 : 0) | (pose.right ? 0x10 : 0) |
                                         (pose.counter & 0x0F));
  return EncodeFrame7(head, w.Finish());
}

std::optional<Pose> DecodeReport(const Frame7& frame) {
  if (BodyLength(frame.head) != kReportBody || frame.body_size != kReportBody) return std::nullopt;
  Frame7Reader r(frame.body.data(), frame.body_size);
  Pose p;
  p.x_m = r.GetSigned(kPositionBits) * kPositionStepM;
  p.y_m = r.GetSigned(kPositionBits) * kPositionStepM;
  p.z_m = r.GetSigned(kPositionBits) * kPositionStepM;
  p.yaw_deg = r.GetSigned(kAngleBits) * kAngleStepDeg;
  p.pitch_deg = r.GetSigned(kAngleBits) * kAngleStepDeg;
  p.roll_deg = r.GetSigned(kAngleBits) * kAngleStepDeg;
  p.left = frame.head & 0x20;
  p.right = frame.head & 0x10;
  p.counter = frame.head & 0x0F;
  if (r.overrun()) return std::nullopt;
  return p;
}

}  // namespace igms::devices::boom
