// Frame7: the compact binary framing shared by the viewer, ranger and camera-platform
// protocols (docs/devices.md). A frame is
//
//   head (1 byte, 0x80..0xFF) | body (N bytes, each 0x00..0x7F) | check (1 byte, 0x00..0x7F)
//
// where N is fixed by the head (each protocol gives a BodyLengthFn) and check is the sum of
// the head and body bytes modulo 128. Only a head byte has its top bit set, so a receiver
// that lost its place resynchronises on the next byte >= 0x80, and a frame cut short is
// detected by a head arriving early. The longest body is kFrame7MaxBody bytes.
//
// Values are packed most significant bit first into the body's 7-bit groups by
// Frame7Writer and read back by Frame7Reader.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace igms::devices {

inline constexpr size_t kFrame7MaxBody = 32;

// Body length for a head byte, or -1 when the head is not one of the protocol's.
using BodyLengthFn = int (*)(uint8_t head);

// Verdict of a byte-fed parser after one byte.
enum class ParseResult {
  kNeedMore,  // the byte was taken; no complete frame yet
  kGood,      // a complete, valid frame ends with this byte
  kBad,       // the byte, or the frame it ended, was rejected (counted); parsing goes on
};

struct Frame7 {
  uint8_t head = 0;
  std::array<uint8_t, kFrame7MaxBody> body{};
  size_t body_size = 0;
};

// Byte-fed, allocation-free, no I/O. Feed bytes one at a time; after kGood, frame() holds
// the frame until the next Feed.
class Frame7Parser {
 public:
  explicit Frame7Parser(BodyLengthFn body_length) : body_length_(body_length) {}

  ParseResult Feed(uint8_t byte);
  const Frame7& frame() const { return frame_; }
  void Reset() { state_ = State::kSync; }

  uint64_t good_frames() const { return good_frames_; }
  uint64_t bad_frames() const { return bad_frames_; }        // truncated or bad check
  uint64_t garbage_bytes() const { return garbage_bytes_; }  // skipped while syncing

 private:
  enum class State { kSync, kBody, kCheck };
  ParseResult StartFrame(uint8_t head);

  BodyLengthFn body_length_;
  State state_ = State::kSync;
  Frame7 frame_;
  size_t expected_ = 0;
  uint8_t sum_ = 0;
  uint64_t good_frames_ = 0;
  uint64_t bad_frames_ = 0;
  uint64_t garbage_bytes_ = 0;
};

// Encodes one frame. head must be >= 0x80, every body byte < 0x80 (programmer error
// otherwise: throws std::invalid_argument).
std::string EncodeFrame7(uint8_t head, std::string_view body);

// Packs unsigned/two's-complement fields MSB first into 7-bit body bytes.
class Frame7Writer {
 public:
  void PutUnsigned(uint32_t value, int bits);
  void PutSigned(int32_t value, int bits);  // clamped to the field's range
  // The body, zero-padded to whole 7-bit bytes.
  std::string Finish() const;

 private:
  std::string bytes_;
  int used_bits_ = 7;  // bits used in the last byte
};

class Frame7Reader {
 public:
  Frame7Reader(const uint8_t* body, size_t size) : body_(body), size_(size) {}
  uint32_t GetUnsigned(int bits);
  int32_t GetSigned(int bits);
  bool overrun() const { return overrun_; }

 private:
  const uint8_t* body_;
  size_t size_;
  size_t bit_ = 0;
  bool overrun_ = false;
};

// Largest magnitude representable in a signed field of `bits` bits.
inline constexpr int32_t SignedFieldMax(int bits) { return (1 << (bits - 1)) - 1; }

}  // namespace igms::devices
