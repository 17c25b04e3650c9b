#include "common/net/framing.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/wire_format_lite.h>

#include <limits>
#include <stdexcept>

#include "common/base/clock.h"

namespace igms::net {

namespace {
constexpr int kMaxVarintBytes = 5;  // a 32-bit length; anything longer is garbage
}

igms::Envelope MakeEnvelope(igms::Envelope::Kind kind, std::uint64_t correlation_id,
                            const std::string& method) {
  igms::Envelope e;
  e.set_kind(kind);
  e.set_method(method);
  auto* h = e.mutable_header();
  h->set_protocol_version(igms::PROTOCOL_VERSION_CURRENT);
  h->set_correlation_id(correlation_id);
  h->set_send_time_unix_ns(UnixNs());
  return e;
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

std::size_t BytesStillNeeded(std::string_view input) {
  std::uint64_t length = 0;
  for (std::size_t i = 0; i < input.size() && i < kMaxVarintBytes; ++i) {
    const auto byte = static_cast<std::uint8_t>(input[i]);
    length |= static_cast<std::uint64_t>(byte & 0x7f) << (7 * i);
    if ((byte & 0x80) == 0) {
      const std::uint64_t total = i + 1 + length;
      return total > input.size() ? static_cast<std::size_t>(total - input.size()) : 0;
    }
  }
  return 0;
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

void AppendFrame(const igms::Envelope& envelope, const google::protobuf::MessageLite& payload,
                 std::string* out) {
  using google::protobuf::io::CodedOutputStream;
  const std::size_t head = envelope.ByteSizeLong();
  const std::size_t body = payload.ByteSizeLong();
  constexpr std::uint32_t kPayloadTag = (igms::Envelope::kPayloadFieldNumber << 3) | 2;
  const std::size_t total = head + CodedOutputStream::VarintSize32(kPayloadTag) +
                            CodedOutputStream::VarintSize64(body) + body;
  if (total > std::numeric_limits<std::uint32_t>::max()) {
    throw std::length_error("message too large to frame");
  }
  const std::size_t at = out->size();
  out->resize(at + CodedOutputStream::VarintSize32(static_cast<std::uint32_t>(total)) + total);
  auto* p = reinterpret_cast<std::uint8_t*>(out->data() + at);
  p = CodedOutputStream::WriteVarint32ToArray(static_cast<std::uint32_t>(total), p);
  p = envelope.SerializeWithCachedSizesToArray(p);
  p = CodedOutputStream::WriteVarint32ToArray(kPayloadTag, p);
  p = CodedOutputStream::WriteVarint64ToArray(body, p);
  payload.SerializeWithCachedSizesToArray(p);
}

bool ParseEnvelopeView(std::string_view frame, igms::Envelope* envelope, std::string_view* payload,
                       std::string* error) {
  using google::protobuf::internal::WireFormatLite;
  if (frame.empty()) {
    *error = "empty frame";
    return false;
  }
  // Walk the top-level fields: the payload is remembered as a view, everything else (a few
  // dozen bytes) is gathered and parsed as usual.
  google::protobuf::io::CodedInputStream in(reinterpret_cast<const std::uint8_t*>(frame.data()),
                                            static_cast<int>(frame.size()));
  std::string rest;
  *payload = {};
  for (;;) {
    const int start = in.CurrentPosition();
    if (start == static_cast<int>(frame.size())) break;
    const std::uint32_t tag = in.ReadTag();
    if (tag == 0) {  // a truncated tag or the invalid tag 0
      *error = "frame of " + std::to_string(frame.size()) + " bytes is not an igms.Envelope";
      return false;
    }
    if (WireFormatLite::GetTagFieldNumber(tag) == igms::Envelope::kPayloadFieldNumber &&
        WireFormatLite::GetTagWireType(tag) == WireFormatLite::WIRETYPE_LENGTH_DELIMITED) {
      std::uint32_t length = 0;
      if (!in.ReadVarint32(&length) || length > frame.size() - in.CurrentPosition()) {
        *error = "envelope payload runs past the end of its frame";
        return false;
      }
      *payload = frame.substr(in.CurrentPosition(), length);
      in.Skip(static_cast<int>(length));
      continue;
    }
    if (!WireFormatLite::SkipField(&in, tag)) {
      *error = "frame of " + std::to_string(frame.size()) + " bytes is not an igms.Envelope";
      return false;
    }
    rest.append(frame.data() + start, in.CurrentPosition() - start);
  }
  if (rest.empty()) {
    *error = "envelope without a valid kind";
    return false;
  }
  return ParseEnvelope(rest, envelope, error);
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
