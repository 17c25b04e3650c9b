#include "common/net/framing.h"

#include <google/protobuf/io/coded_stream.h>

#include <limits>

namespace igms::net {

namespace {
constexpr int kMaxVarintBytes = 5;  // a 32-bit length; anything longer is garbage
}

DecodeResult DecodeFrame(std::string_view input, std::size_t max_frame_bytes) {
  DecodeResult result;
  std::uint64_t length = 0;
  std::size_t i = 0;
  for (;; ++i) {
    if (i >= input.size()) return result;  // need more
    if (i >= kMaxVarintBytes) {
      result.status = DecodeStatus::kError;
      result.error = "frame length prefix longer than 5 bytes";
      return result;
    }
    const auto byte = static_cast<std::uint8_t>(input[i]);
    length |= static_cast<std::uint64_t>(byte & 0x7f) << (7 * i);
    if ((byte & 0x80) == 0) break;
  }
  const std::size_t prefix = i + 1;
  if (length > max_frame_bytes) {
    result.status = DecodeStatus::kError;
    result.error = "frame of " + std::to_string(length) + " bytes exceeds the limit of " +
                   std::to_string(max_frame_bytes);
    return result;
  }
  if (input.size() - prefix < length) return result;  // need more
  result.status = DecodeStatus::kFrame;
  result.frame = input.substr(prefix, static_cast<std::size_t>(length));
  result.consumed = prefix + static_cast<std::size_t>(length);
  return result;
}

void AppendFrame(const google::protobuf::MessageLite& message, std::string* out) {
  const std::size_t size = message.ByteSizeLong();
  if (size > std::numeric_limits<std::uint32_t>::max()) {
    throw std::length_error("message too large to frame");
  }
  std::uint8_t prefix[kMaxVarintBytes];
  std::uint8_t* end = google::protobuf::io::CodedOutputStream::WriteVarint32ToArray(
      static_cast<std::uint32_t>(size), prefix);
  out->append(reinterpret_cast<const char*>(prefix), end - prefix);
  const std::size_t at = out->size();
  out->resize(at + size);
  message.SerializeWithCachedSizesToArray(reinterpret_cast<std::uint8_t*>(out->data() + at));
}

std::string EncodeFrame(const google::protobuf::MessageLite& message) {
  std::string out;
  AppendFrame(message, &out);
  return out;
}

bool ParseEnvelope(std::string_view frame, igms::Envelope* envelope, std::string* error) {
  if (frame.empty()) {
    *error = "empty frame";
    return false;
  }
  if (!envelope->ParseFromArray(frame.data(), static_cast<int>(frame.size()))) {
    *error = "frame of " + std::to_string(frame.size()) + " bytes is not an igms.Envelope";
    return false;
  }
  if (envelope->kind() == igms::Envelope::KIND_UNSPECIFIED ||
      !igms::Envelope::Kind_IsValid(envelope->kind())) {
    *error = "envelope without a valid kind";
    return false;
  }
  return true;
}

}  // namespace igms::net
