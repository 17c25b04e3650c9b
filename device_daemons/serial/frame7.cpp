#include "device_daemons/serial/frame7.h"

#include <algorithm>
#include <stdexcept>

namespace igms::devices {

ParseResult Frame7Parser::StartFrame(uint8_t head) {
  const int length = body_length_(head);
  if (length < 0 || static_cast<size_t>(length) > kFrame7MaxBody) {
    ++garbage_bytes_;
    state_ = State::kSync;
    return ParseResult::kBad;
  }
  frame_.head = head;
  frame_.body_size = 0;
  expected_ = static_cast<size_t>(length);
  sum_ = head;
  state_ = expected_ == 0 ? State::kCheck : State::kBody;
  return ParseResult::kNeedMore;
}

ParseResult Frame7Parser::Feed(uint8_t byte) {
  if (byte & 0x80) {
    // A head always starts a frame; one arriving mid-frame means the frame was cut short.
    if (state_ != State::kSync) {
      ++bad_frames_;
      StartFrame(byte);
      return ParseResult::kBad;
    }
    return StartFrame(byte);
  }
  switch (state_) {
    case State::kSync:
      ++garbage_bytes_;
      return ParseResult::kBad;
    case State::kBody:
      frame_.body[frame_.body_size++] = byte;
      sum_ = static_cast<uint8_t>(sum_ + byte);
      if (frame_.body_size == expected_) state_ = State::kCheck;
      return ParseResult::kNeedMore;
    case State::kCheck:
      state_ = State::kSync;
      if ((sum_ & 0x7F) != byte) {
        ++bad_frames_;
        return ParseResult::kBad;
      }
      ++good_frames_;
      return ParseResult::kGood;
  }
  return ParseResult::kBad;
}

std::string EncodeFrame7(uint8_t head, std::string_view body) {
  if (!(head & 0x80)) throw std::invalid_argument("Frame7 head byte without its top bit");
  std::string out;
  out.reserve(body.size() + 2);
  out.push_back(static_cast<char>(head));
  uint8_t sum = head;
  for (char c : body) {
    const auto b = static_cast<uint8_t>(c);
    if (b & 0x80) throw std::invalid_argument("Frame7 body byte with its top bit set");
    sum = static_cast<uint8_t>(sum + b);
    out.push_back(c);
  }
  out.push_back(static_cast<char>(sum & 0x7F));
  return out;
}

void Frame7Writer::PutUnsigned(uint32_t value, int bits) {
  for (int i = bits - 1; i >= 0; --i) {
    if (used_bits_ == 7) {
      bytes_.push_back(0);
      used_bits_ = 0;
    }
    const uint8_t bit = (value >> i) & 1U;
    bytes_.back() = static_cast<char>(bytes_.back() | (bit << (6 - used_bits_)));
    ++used_bits_;
  }
}

void Frame7Writer::PutSigned(int32_t value, int bits) {
  const int32_t max = SignedFieldMax(bits);
  value = std::clamp(value, -max - 1, max);
  PutUnsigned(static_cast<uint32_t>(value) & ((1U << bits) - 1U), bits);
}

std::string Frame7Writer::Finish() const { return bytes_; }

uint32_t Frame7Reader::GetUnsigned(int bits) {
  uint32_t value = 0;
  for (int i = 0; i < bits; ++i) {
    const size_t byte = bit_ / 7;
    if (byte >= size_) {
      overrun_ = true;
      return 0;
    }
    const uint32_t b = (body_[byte] >> (6 - bit_ % 7)) & 1U;
    value = (value << 1) | b;
    ++bit_;
  }
  return value;
}

int32_t Frame7Reader::GetSigned(int bits) {
  const uint32_t raw = GetUnsigned(bits);
  const uint32_t sign = 1U << (bits - 1);
  return static_cast<int32_t>(raw ^ sign) - static_cast<int32_t>(sign);
}

}  // namespace igms::devices
