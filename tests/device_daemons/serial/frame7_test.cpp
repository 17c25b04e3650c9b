#include "device_daemons/serial/frame7.h"

#include <gtest/gtest.h>

#include <vector>

namespace igms::devices {
namespace {

int TestBodyLength(uint8_t head) {
  if (head == 0x81) return 3;
  if (head == 0x82) return 0;
  return -1;
}

std::vector<ParseResult> FeedAll(Frame7Parser& p, const std::string& bytes) {
  std::vector<ParseResult> out;
  for (char c : bytes) out.push_back(p.Feed(static_cast<uint8_t>(c)));
  return out;
}

TEST(Frame7, RoundTripsOneFrame) {
  const std::string frame = EncodeFrame7(0x81, std::string("\x01\x7F\x40", 3));
  ASSERT_EQ(frame.size(), 5u);
  EXPECT_EQ(static_cast<uint8_t>(frame[4]), (0x81 + 0x01 + 0x7F + 0x40) & 0x7F);
  Frame7Parser p(TestBodyLength);
  const auto results = FeedAll(p, frame);
  for (size_t i = 0; i + 1 < results.size(); ++i) EXPECT_EQ(results[i], ParseResult::kNeedMore);
  EXPECT_EQ(results.back(), ParseResult::kGood);
  EXPECT_EQ(p.frame().head, 0x81);
  ASSERT_EQ(p.frame().body_size, 3u);
  EXPECT_EQ(p.frame().body[1], 0x7F);
}

TEST(Frame7, EmptyBodyFrame) {
  Frame7Parser p(TestBodyLength);
  const auto results = FeedAll(p, EncodeFrame7(0x82, ""));
  EXPECT_EQ(results, (std::vector{ParseResult::kNeedMore, ParseResult::kGood}));
}

TEST(Frame7, ResynchronisesAfterGarbageAndCountsIt) {
  Frame7Parser p(TestBodyLength);
  const std::string good = EncodeFrame7(0x81, "abc");
  // Garbage: body-range bytes while syncing, an unknown head, and a head-range byte.
  const std::string stream = std::string("xyz\x90q", 5) + good + std::string("\x00\x01", 2) + good;
  const auto results = FeedAll(p, stream);
  EXPECT_EQ(std::count(results.begin(), results.end(), ParseResult::kGood), 2);
  EXPECT_EQ(p.garbage_bytes(), 7u);
  EXPECT_EQ(p.bad_frames(), 0u);
}

TEST(Frame7, TruncatedFrameIsBadAndTheNextOneParses) {
  Frame7Parser p(TestBodyLength);
  const std::string good = EncodeFrame7(0x81, "abc");
  const auto results = FeedAll(p, good.substr(0, 3) + good);
  EXPECT_EQ(results[3], ParseResult::kBad);  // the early head
  EXPECT_EQ(results.back(), ParseResult::kGood);
  EXPECT_EQ(p.bad_frames(), 1u);
  EXPECT_EQ(p.good_frames(), 1u);
}

TEST(Frame7, BadChecksumIsRejected) {
  Frame7Parser p(TestBodyLength);
  std::string frame = EncodeFrame7(0x81, "abc");
  frame[2] = 'B';
  EXPECT_EQ(FeedAll(p, frame).back(), ParseResult::kBad);
  EXPECT_EQ(p.bad_frames(), 1u);
}

TEST(Frame7, EncodeRejectsProgrammerErrors) {
  EXPECT_THROW(EncodeFrame7(0x01, ""), std::invalid_argument);
  EXPECT_THROW(EncodeFrame7(0x81, "\x80"), std::invalid_argument);
}

TEST(Frame7, BitPackingRoundTripsAndClamps) {
  Frame7Writer w;
  w.PutSigned(-2048, 12);
  w.PutSigned(2047, 12);
  w.PutUnsigned(5, 3);
  w.PutSigned(99999, 13);  // clamped to 4095
  w.PutSigned(-1, 21);
  const std::string body = w.Finish();
  EXPECT_EQ(body.size(), (12 + 12 + 3 + 13 + 21 + 6) / 7);
  for (char c : body) EXPECT_LT(static_cast<uint8_t>(c), 0x80);
  Frame7Reader r(reinterpret_cast<const uint8_t*>(body.data()), body.size());
  EXPECT_EQ(r.GetSigned(12), -2048);
  EXPECT_EQ(r.GetSigned(12), 2047);
  EXPECT_EQ(r.GetUnsigned(3), 5u);
  EXPECT_EQ(r.GetSigned(13), 4095);
  EXPECT_EQ(r.GetSigned(21), -1);
  EXPECT_FALSE(r.overrun());
  r.GetUnsigned(20);
  EXPECT_TRUE(r.overrun());
}

}  // namespace
}  // namespace igms::devices
