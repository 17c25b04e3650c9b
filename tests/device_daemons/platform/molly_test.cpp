#include <gtest/gtest.h>

#include <cmath>

#include "device_daemons/platform/molly_protocol.h"
#include "device_daemons/platform/molly_sim.h"

namespace igms::devices {
namespace {

using molly::Ticks;

std::optional<molly::Message> ParseOne(Frame7Parser& parser, const std::string& bytes) {
  std::optional<molly::Message> out;
  for (char c : bytes) {
    if (parser.Feed(static_cast<uint8_t>(c)) == ParseResult::kGood)
      out = molly::Decode(parser.frame());
  }
  return out;
}

TEST(MollyProtocol, ThesisTickSizes) {
  EXPECT_NEAR(molly::kYawDegPerTick, 3.684e-3, 1e-6);
  EXPECT_NEAR(molly::kPitchRollDegPerTick, 1.750e-2, 1e-5);
}

TEST(MollyProtocol, EveryMessageRoundTrips) {
  Frame7Parser p(molly::BodyLength);
  const Ticks t{-48000, 5000, -1234};
  auto m = ParseOne(p, molly::EncodeSet(t));
  ASSERT_TRUE(m);
  EXPECT_EQ(m->head, molly::kSet);
  EXPECT_EQ(m->ticks, t);
  EXPECT_EQ(molly::EncodeSet(t).size(), 9u);
  m = ParseOne(p, molly::EncodeSpeed(250));
  ASSERT_TRUE(m);
  EXPECT_EQ(m->steps_per_move, 250u);
  EXPECT_EQ(ParseOne(p, molly::EncodeQuery())->head, molly::kQuery);
  EXPECT_EQ(ParseOne(p, molly::EncodeZero())->head, molly::kZero);
  m = ParseOne(p, molly::EncodeOrientation(t, true, false));
  ASSERT_TRUE(m);
  EXPECT_EQ(m->head, molly::kOrientation);
  EXPECT_EQ(m->ticks, t);
  EXPECT_TRUE(m->moving);
  EXPECT_FALSE(m->at_limit);
  m = ParseOne(p, molly::EncodeAck(molly::kSet));
  ASSERT_TRUE(m);
  EXPECT_EQ(m->acked, molly::kSet);
  EXPECT_EQ(p.bad_frames(), 0u);
}

TEST(MollyProtocol, RejectsGarbageAndOutOfRangeFields) {
  Frame7Parser p(molly::BodyLength);
  // An ACK naming something that is no command, a zero speed, garbage, then a good query.
  const std::string stream = molly::EncodeAck(0xA1) +
                             EncodeFrame7(molly::kSpeed, std::string(2, '\0')) +
                             std::string("\xFF\x7F\x10", 3) + molly::EncodeQuery();
  int good = 0, decoded = 0;
  for (char c : stream) {
    if (p.Feed(static_cast<uint8_t>(c)) == ParseResult::kGood) {
      ++good;
      if (molly::Decode(p.frame())) ++decoded;
    }
  }
  EXPECT_EQ(good, 3);
  EXPECT_EQ(decoded, 1);
  EXPECT_EQ(p.garbage_bytes(), 3u);
}

TEST(MollySim, MovesWithFiniteSpeedAndQuantisedEncoders) {
  MollySim sim;
  const Ticks target{static_cast<int32_t>(std::lround(45.0 / molly::kYawDegPerTick)),
                     static_cast<int32_t>(std::lround(-10.0 / molly::kPitchRollDegPerTick)), 0};
  Frame7Parser p(molly::BodyLength);
  sim.OnInput(molly::EncodeSet(target), 0);
  sim.AdvanceTo(100'000'000);  // 0.1 s: still on the way
  EXPECT_TRUE(sim.Moving());
  EXPECT_GT(sim.Encoders().yaw, 0);
  EXPECT_LT(sim.Encoders().yaw, target.yaw / 2);
  sim.AdvanceTo(3'000'000'000);  // 45 degrees at 90 deg/s with ramps: under 1 s
  EXPECT_FALSE(sim.Moving());
  EXPECT_EQ(sim.Encoders(), target);
  const auto truth = sim.TrueDegrees();
  EXPECT_NEAR(truth[0], 45.0, molly::kYawDegPerTick);
  // The reply to a query carries the encoders.
  const auto out = sim.OnInput(molly::EncodeQuery(), 3'000'000'000);
  ASSERT_EQ(out.size(), 1u);
  const auto m = ParseOne(p, out[0]);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->ticks, target);
  EXPECT_FALSE(m->moving);
}

TEST(MollySim, StepsPerMoveSlowTheMove) {
  MollySim sim;
  sim.OnInput(molly::EncodeSpeed(400), 0);  // 400 steps at 200 Hz: a 2 s move
  sim.OnInput(molly::EncodeSet({static_cast<int32_t>(10.0 / molly::kYawDegPerTick), 0, 0}), 0);
  sim.AdvanceTo(1'000'000'000);
  EXPECT_TRUE(sim.Moving());
  EXPECT_NEAR(sim.TrueDegrees()[0], 5.0, 0.5);
  sim.AdvanceTo(2'500'000'000);
  EXPECT_FALSE(sim.Moving());
}

TEST(MollySim, LimitsStopShortOfTheCommand) {
  MollySim sim;
  sim.OnInput(molly::EncodeSet({0, static_cast<int32_t>(80.0 / molly::kPitchRollDegPerTick), 0}),
              0);
  sim.AdvanceTo(5'000'000'000);
  EXPECT_NEAR(molly::PitchRollDeg(sim.Encoders().pitch), 60.0, molly::kPitchRollDegPerTick);
  Frame7Parser p(molly::BodyLength);
  const auto m = ParseOne(p, sim.OnInput(molly::EncodeQuery(), 5'000'000'000)[0]);
  ASSERT_TRUE(m);
  EXPECT_TRUE(m->at_limit);
}

TEST(MollySim, BacklashLeavesTheCameraOffWhileEncodersReadZero) {
  MollySimOptions options;
  options.backlash_deg = 1.59;  // thesis 4.4
  MollySim sim(options);
  const auto start = sim.TrueDegrees()[1];
  sim.OnInput(molly::EncodeSet(
                  {0, static_cast<int32_t>(std::lround(20.0 / molly::kPitchRollDegPerTick)), 0}),
              0);
  sim.AdvanceTo(2'000'000'000);
  sim.OnInput(molly::EncodeSet({0, 0, 0}), 2'000'000'000);
  sim.AdvanceTo(4'000'000'000);
  EXPECT_EQ(sim.Encoders().pitch, 0);
  EXPECT_NEAR(sim.TrueDegrees()[1] - start, 1.59, 1e-9);
  // Yaw has no backlash modelled: the thesis found it accurate to a pixel.
  EXPECT_EQ(sim.TrueDegrees()[0], 0.0);
}

TEST(MollySim, ResetZeroMakesTheCurrentOrientationZero) {
  MollySim sim;
  sim.OnInput(molly::EncodeSet({1000, 100, -100}), 0);
  sim.AdvanceTo(2'000'000'000);
  const auto acks = sim.OnInput(molly::EncodeZero(), 2'000'000'000);
  ASSERT_EQ(acks.size(), 1u);
  EXPECT_EQ(sim.Encoders(), (Ticks{0, 0, 0}));
  sim.AdvanceTo(3'000'000'000);
  EXPECT_FALSE(sim.Moving());
}

}  // namespace
}  // namespace igms::devices
