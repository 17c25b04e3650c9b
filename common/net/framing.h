// Framing of IGMS messages on a byte stream: each frame is a base-128 varint length
// followed by that many bytes of a serialized igms.Envelope (protobuf's "delimited" form,
// the same bytes google::protobuf::util::SerializeDelimitedToOstream writes).
//
// The decoder is pure (no I/O): feed it whatever bytes arrived, in any split, and it says
// whether a whole frame is ready, more bytes are needed, or the stream is bad. A stream is
// bad when a length is longer than 5 varint bytes, or larger than the configured limit; the
// connection cannot be resynchronised after that and must be closed.
#pragma once

#include <google/protobuf/message_lite.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "igms/common.pb.h"

namespace igms::net {

// The default frame limit: room for a 512x480 stereo pair and then some. Video and other
// bulk services raise it in their options.
inline constexpr std::size_t kDefaultMaxFrameBytes = 4u << 20;

enum class DecodeStatus { kNeedMore, kFrame, kError };

struct DecodeResult {
  DecodeStatus status = DecodeStatus::kNeedMore;
  // kFrame: the frame's body (without its length prefix), pointing into the input.
  std::string_view frame;
  // kFrame: bytes of input used by this frame, prefix included.
  std::size_t consumed = 0;
  // kError: why, for the log.
  std::string error;
};

// An envelope of the current protocol version, stamped with the wall clock now.
igms::Envelope MakeEnvelope(igms::Envelope::Kind kind, std::uint64_t correlation_id,
                            const std::string& method);

// Looks for one frame at the start of `input`.
DecodeResult DecodeFrame(std::string_view input, std::size_t max_frame_bytes);

// How many more bytes the frame at the start of `input` needs (0 when it is complete or its
// length is not known yet), so a reader can size its buffer once for a large frame.
std::size_t BytesStillNeeded(std::string_view input);

// Appends the varint length prefix and the serialized message to `out`.
void AppendFrame(const google::protobuf::MessageLite& message, std::string* out);
std::string EncodeFrame(const google::protobuf::MessageLite& message);

// Frames `envelope` (whose own payload must be empty) with `payload` serialized straight
// into the frame as the envelope's payload field: one copy instead of two.
void AppendFrame(const igms::Envelope& envelope, const google::protobuf::MessageLite& payload,
                 std::string* out);

// Parses a frame body into an envelope and checks the fields every peer relies on.
// Returns false with a reason for a frame that does not parse or makes no sense.
bool ParseEnvelope(std::string_view frame, igms::Envelope* envelope, std::string* error);
// The same, except that the payload is not copied: *payload points into `frame` and
// envelope->payload() stays empty.
bool ParseEnvelopeView(std::string_view frame, igms::Envelope* envelope, std::string_view* payload,
                       std::string* error);

}  // namespace igms::net
