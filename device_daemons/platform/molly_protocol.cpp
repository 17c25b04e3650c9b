#include "device_daemons/platform/molly_protocol.h"

#include <algorithm>

namespace igms::devices::molly {

int BodyLength(uint8_t head) {
  switch (head) {
    case kSet:
      return 7;
    case kSpeed:
      return 2;
    case kQuery:
    case kZero:
      return 0;
    case kAck:
      return 1;
    default:
      break;
  }
  if ((head & ~(kFlagMoving | kFlagLimit)) == kOrientation) return 7;
  return -1;
}

namespace {
std::string TicksBody(const Ticks& t) {
  Frame7Writer w;
  w.PutSigned(t.yaw, kYawBits);
  w.PutSigned(t.pitch, kPitchRollBits);
  w.PutSigned(t.roll, kPitchRollBits);
  return w.Finish();
}

Ticks ReadTicks(const Frame7& f) {
  Frame7Reader r(f.body.data(), f.body_size);
  Ticks t;
  t.yaw = r.GetSigned(kYawBits);
  t.pitch = r.GetSigned(kPitchRollBits);
  t.roll = r.GetSigned(kPitchRollBits);
  return t;
}
}  // namespace

std::string EncodeSet(const Ticks& ticks) { return EncodeFrame7(kSet, TicksBody(ticks)); }

std::string EncodeSpeed(uint32_t steps) {
  Frame7Writer w;
  w.PutUnsigned(std::clamp<uint32_t>(steps, 1, kMaxStepsPerMove), 14);
  return EncodeFrame7(kSpeed, w.Finish());
}

std::string EncodeQuery() { return EncodeFrame7(kQuery, ""); }
std::string EncodeZero() { return EncodeFrame7(kZero, ""); }

std::string EncodeOrientation(const Ticks& ticks, bool moving, bool at_limit) {
  const auto head =
      static_cast<uint8_t>(kOrientation | (moving ? kFlagMoving : 0) | (at_limit ? kFlagLimit : 0));
  return EncodeFrame7(head, TicksBody(ticks));
}

std::string EncodeAck(uint8_t command_head) {
  return EncodeFrame7(kAck, std::string(1, static_cast<char>(command_head & 0x7F)));
}

std::optional<Message> Decode(const Frame7& f) {
  const int length = BodyLength(f.head);
  if (length < 0 || static_cast<size_t>(length) != f.body_size) return std::nullopt;
  Message m;
  m.head = f.head;
  switch (f.head) {
    case kSet:
      m.ticks = ReadTicks(f);
      return m;
    case kSpeed: {
      Frame7Reader r(f.body.data(), f.body_size);
      m.steps_per_move = r.GetUnsigned(14);
      if (m.steps_per_move == 0) return std::nullopt;
      return m;
    }
    case kQuery:
    case kZero:
      return m;
    case kAck:
      m.acked = static_cast<uint8_t>(f.body[0] | 0x80);
      if (BodyLength(m.acked) < 0 || m.acked == kAck || (m.acked & 0xF0) == kOrientation)
        return std::nullopt;
      return m;
    default:
      m.head = kOrientation;
      m.ticks = ReadTicks(f);
      m.moving = f.head & kFlagMoving;
      m.at_limit = f.head & kFlagLimit;
      return m;
  }
}

}  // namespace igms::devices::molly
