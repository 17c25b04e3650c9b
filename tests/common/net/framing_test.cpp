// Framing: round trips, split and coalesced input, and every kind of bad frame.
#include "common/net/framing.h"

#include <gtest/gtest.h>

#include <random>

namespace igms::net {
namespace {

igms::Envelope Sample(std::uint64_t id, std::size_t payload_bytes) {
  igms::Envelope e;
  e.set_kind(igms::Envelope::REQUEST);
  e.set_method("igms.Server.Ping");
  e.mutable_header()->set_correlation_id(id);
  e.mutable_header()->set_protocol_version(igms::PROTOCOL_VERSION_CURRENT);
  e.set_payload(std::string(payload_bytes, 'x'));
  return e;
}

TEST(Framing, RoundTripsEveryKind) {
  for (int k = igms::Envelope::HELLO; k <= igms::Envelope::HEARTBEAT; ++k) {
    igms::Envelope e = Sample(k, 10);
    e.set_kind(static_cast<igms::Envelope::Kind>(k));
    const std::string bytes = EncodeFrame(e);
    DecodeResult r = DecodeFrame(bytes, kDefaultMaxFrameBytes);
    ASSERT_EQ(r.status, DecodeStatus::kFrame);
    EXPECT_EQ(r.consumed, bytes.size());
    igms::Envelope back;
    std::string error;
    ASSERT_TRUE(ParseEnvelope(r.frame, &back, &error)) << error;
    EXPECT_EQ(back.SerializeAsString(), e.SerializeAsString());
  }
}

TEST(Framing, SplitAtEveryByte) {
  const std::string bytes = EncodeFrame(Sample(7, 300));  // two-byte length prefix
  for (std::size_t cut = 0; cut < bytes.size(); ++cut) {
    EXPECT_EQ(DecodeFrame(std::string_view(bytes).substr(0, cut), kDefaultMaxFrameBytes).status,
              DecodeStatus::kNeedMore)
        << "cut at " << cut;
  }
  EXPECT_EQ(DecodeFrame(bytes, kDefaultMaxFrameBytes).status, DecodeStatus::kFrame);
}

TEST(Framing, CoalescedFramesComeOutInOrder) {
  std::string stream;
  for (std::uint64_t i = 1; i <= 50; ++i) AppendFrame(Sample(i, i * 37), &stream);
  std::string_view rest(stream);
  for (std::uint64_t i = 1; i <= 50; ++i) {
    DecodeResult r = DecodeFrame(rest, kDefaultMaxFrameBytes);
    ASSERT_EQ(r.status, DecodeStatus::kFrame);
    igms::Envelope e;
    std::string error;
    ASSERT_TRUE(ParseEnvelope(r.frame, &e, &error));
    EXPECT_EQ(e.header().correlation_id(), i);
    EXPECT_EQ(e.payload().size(), i * 37);
    rest.remove_prefix(r.consumed);
  }
  EXPECT_TRUE(rest.empty());
}

TEST(Framing, OversizeFrameIsAnErrorBeforeItsBodyArrives) {
  const std::string bytes = EncodeFrame(Sample(1, 5000));
  // Only the prefix: the limit is checked as soon as the length is known.
  DecodeResult r = DecodeFrame(std::string_view(bytes).substr(0, 3), 1000);
  EXPECT_EQ(r.status, DecodeStatus::kError);
  EXPECT_NE(r.error.find("exceeds the limit of 1000"), std::string::npos) << r.error;
}

TEST(Framing, OverlongLengthPrefixIsAnError) {
  const std::string bytes(6, '\xff');
  DecodeResult r = DecodeFrame(bytes, kDefaultMaxFrameBytes);
  EXPECT_EQ(r.status, DecodeStatus::kError);
}

TEST(Framing, ZeroLengthFrameDecodesButIsNotAnEnvelope) {
  const std::string bytes(1, '\0');
  DecodeResult r = DecodeFrame(bytes, kDefaultMaxFrameBytes);
  ASSERT_EQ(r.status, DecodeStatus::kFrame);
  EXPECT_EQ(r.consumed, 1u);
  igms::Envelope e;
  std::string error;
  EXPECT_FALSE(ParseEnvelope(r.frame, &e, &error));
  EXPECT_EQ(error, "empty frame");
}

TEST(Framing, GarbageAndTruncatedBodiesAreRejected) {
  std::string bytes = EncodeFrame(Sample(3, 40));
  igms::Envelope e;
  std::string error;
  // Truncated: the body is cut short inside a field.
  EXPECT_FALSE(ParseEnvelope(std::string_view(bytes).substr(1, 20), &e, &error));
  // Garbage: random bytes never crash the parser; most are rejected.
  std::mt19937 rng(42);
  int rejected = 0;
  for (int i = 0; i < 2000; ++i) {
    std::string junk(1 + rng() % 64, '\0');
    for (auto& c : junk) c = static_cast<char>(rng());
    if (!ParseEnvelope(junk, &e, &error)) ++rejected;
  }
  EXPECT_GT(rejected, 1500);
  // A valid envelope with an unknown kind is rejected too.
  igms::Envelope odd = Sample(1, 0);
  odd.set_kind(static_cast<igms::Envelope::Kind>(99));
  EXPECT_FALSE(ParseEnvelope(odd.SerializeAsString(), &e, &error));
}

TEST(Framing, ViewParseMatchesFullParseWithoutCopyingThePayload) {
  igms::Envelope e = Sample(9, 100000);
  const std::string bytes = EncodeFrame(e);
  DecodeResult r = DecodeFrame(bytes, kDefaultMaxFrameBytes);
  ASSERT_EQ(r.status, DecodeStatus::kFrame);
  igms::Envelope head;
  std::string_view payload;
  std::string error;
  ASSERT_TRUE(ParseEnvelopeView(r.frame, &head, &payload, &error)) << error;
  EXPECT_TRUE(head.payload().empty());
  EXPECT_EQ(payload, e.payload());
  EXPECT_GE(payload.data(), bytes.data());
  EXPECT_LE(payload.data() + payload.size(), bytes.data() + bytes.size());
  EXPECT_EQ(head.header().correlation_id(), 9u);
  EXPECT_EQ(head.method(), e.method());
  // Truncated and empty frames are refused like the full parse refuses them.
  EXPECT_FALSE(ParseEnvelopeView(r.frame.substr(0, r.frame.size() - 10), &head, &payload, &error));
  EXPECT_FALSE(ParseEnvelopeView({}, &head, &payload, &error));
}

TEST(Framing, SingleCopyFramingEqualsFramingAFilledEnvelope) {
  igms::Envelope head = Sample(4, 0);
  igms::PingResponse body;
  body.set_server_name("video");
  body.set_program(std::string(70000, 'p'));
  std::string framed;
  AppendFrame(head, body, &framed);
  igms::Envelope full = head;
  full.set_payload(body.SerializeAsString());
  DecodeResult a = DecodeFrame(framed, kDefaultMaxFrameBytes);
  ASSERT_EQ(a.status, DecodeStatus::kFrame);
  EXPECT_EQ(a.consumed, framed.size());
  igms::Envelope back;
  std::string error;
  ASSERT_TRUE(ParseEnvelope(a.frame, &back, &error)) << error;
  EXPECT_EQ(back.SerializeAsString(), full.SerializeAsString());
}

}  // namespace
}  // namespace igms::net
