#include "device_daemons/joystick/cerealbox_protocol.h"

#include <gtest/gtest.h>

#include "device_daemons/joystick/flybox_sim.h"

namespace igms::devices::cerealbox {
namespace {

std::vector<ParseResult> FeedAll(ReportParser& p, const std::string& bytes) {
  std::vector<ParseResult> out;
  for (char c : bytes) out.push_back(p.Feed(static_cast<uint8_t>(c)));
  return out;
}

Report Sample() {
  Report r;
  r.analog = {-1.0, 1.0, 0.25, -0.5, 0.0, 0, 0, 0};
  r.digital = 0x1A5;  // buttons 1, 3, 6, 8 and the trigger
  return r;
}

TEST(CerealBox, IdentIs44CharactersWithVersionWhereDriversLook) {
  const std::string ident = IdentString('F');
  ASSERT_EQ(ident.size(), kIdentLength);
  EXPECT_EQ(ident.substr(0, 25), "Copyright (c), BG Systems");
  EXPECT_EQ(ident[38] - '0', 3);
  EXPECT_EQ(ident[40] - '0', 0);
  EXPECT_EQ(ident[41] - '0', 7);
  char type = 0;
  std::string version;
  ASSERT_TRUE(ParseIdent(ident, &type, &version));
  EXPECT_EQ(type, 'F');
  EXPECT_EQ(version, "3.07");
  EXPECT_FALSE(ParseIdent(ident.substr(1) + "x", &type, &version));
}

TEST(CerealBox, ConfigCommandMatchesTheBoxLayout) {
  const std::string cmd = ConfigCommand(kFlyBoxLayout);
  ASSERT_EQ(cmd.size(), 10u);
  EXPECT_EQ(cmd[0], 'c');
  EXPECT_EQ(cmd[1], 0x0F + kOffset);                  // analog 1-4
  EXPECT_EQ(cmd[2], (0x01 | (0x03 << 4)) + kOffset);  // analog 5, digital banks 1-2
  EXPECT_EQ(cmd[9], '\n');
  Layout back;
  ASSERT_TRUE(ParseConfig(cmd.substr(1, 8), &back));
  EXPECT_EQ(back.analog_mask, 0x1F);
  EXPECT_EQ(back.digital_banks, 2);
  EXPECT_EQ(back.encoder_mask, 0);
  EXPECT_FALSE(ParseConfig("short", &back));
  EXPECT_FALSE(ParseConfig(std::string(8, '\x01'), &back));
}

TEST(CerealBox, ReportRoundTripsWithin12BitResolution) {
  const std::string bytes = EncodeReport(kFlyBoxLayout, Sample());
  ASSERT_EQ(bytes.size(), kFlyBoxLayout.report_length());
  EXPECT_EQ(bytes.size(), 16u);  // 16.7 ms at 9600 baud: fits the 50 Hz cycle
  EXPECT_EQ(bytes.front(), 'p');
  EXPECT_EQ(bytes.back(), '\n');
  ReportParser p(kFlyBoxLayout);
  EXPECT_EQ(FeedAll(p, bytes).back(), ParseResult::kGood);
  const Report& r = p.report();
  ASSERT_EQ(r.analog_count, 5);
  EXPECT_DOUBLE_EQ(r.analog[0], -1.0);
  EXPECT_DOUBLE_EQ(r.analog[1], 1.0);
  EXPECT_NEAR(r.analog[2], 0.25, 1.0 / 4095);
  EXPECT_NEAR(r.analog[3], -0.5, 1.0 / 4095);
  EXPECT_NEAR(r.analog[4], 0.0, 1.0 / 4095);
  EXPECT_EQ(r.digital, 0x1A5u);
}

TEST(CerealBox, EncodersAreSigned24Bit) {
  Layout layout;
  layout.encoder_mask = 0x03;
  Report in = Sample();
  in.encoders = {-5, 123456, 0, 0, 0, 0, 0, 0};
  ReportParser p(layout);
  EXPECT_EQ(FeedAll(p, EncodeReport(layout, in)).back(), ParseResult::kGood);
  EXPECT_EQ(p.report().encoders[0], -5);
  EXPECT_EQ(p.report().encoders[1], 123456);
}

TEST(CerealBox, ResynchronisesAfterGarbageAndTruncation) {
  const std::string good = EncodeReport(kFlyBoxLayout, Sample());
  ReportParser p(kFlyBoxLayout);
  // Garbage, a report cut short by the next, a report with a bad character, then good.
  std::string bad_char = good;
  bad_char[5] = '\x7E';
  const std::string stream = "junk\x01\xFF" + good.substr(0, 7) + good + bad_char + good;
  const auto results = FeedAll(p, stream);
  EXPECT_EQ(std::count(results.begin(), results.end(), ParseResult::kGood), 2);
  EXPECT_EQ(p.good_frames(), 2u);
  EXPECT_EQ(p.bad_frames(), 2u);  // the truncated one and the bad character
  EXPECT_GE(p.garbage_bytes(), 6u);
}

TEST(CerealBox, MissingNewlineIsBad) {
  std::string bytes = EncodeReport(kFlyBoxLayout, Sample());
  bytes.back() = '!';
  ReportParser p(kFlyBoxLayout);
  EXPECT_EQ(FeedAll(p, bytes).back(), ParseResult::kBad);
  EXPECT_EQ(p.good_frames(), 0u);
}

TEST(FlyBoxSim, AnswersTheCommandsADriverSends) {
  FlyBoxSim sim;
  JoystickState s;
  s.set_x(0.5);
  s.set_trigger(true);
  s.set_buttons(0x81);
  sim.Set(s);
  auto out = sim.OnInput("T", 0);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0], IdentString('F'));
  out = sim.OnInput(ConfigCommand(kFlyBoxLayout), 0);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0], "a\n");
  out = sim.OnInput("pE", 0);  // a driver that sends 'p' followed by another byte
  ASSERT_EQ(out.size(), 1u);
  ReportParser p(kFlyBoxLayout);
  EXPECT_EQ(FeedAll(p, out[0]).back(), ParseResult::kGood);
  EXPECT_NEAR(p.report().analog[0], 0.5, 1.0 / 4095);
  EXPECT_EQ(p.report().digital, 0x181u);
  EXPECT_EQ(sim.OnInput("h", 0), std::vector<std::string>{"a\n"});
  // Continuous mode: a report every 20 ms of simulated time.
  sim.OnInput("C", 1'000'000'000);
  int64_t wake = INT64_MAX;
  EXPECT_EQ(sim.Poll(1'000'000'000, &wake).size(), 1u);
  EXPECT_EQ(wake, 1'020'000'000);
  EXPECT_EQ(sim.Poll(1'010'000'000, &wake).size(), 0u);
  EXPECT_EQ(sim.Poll(1'020'000'000, &wake).size(), 1u);
}

}  // namespace
}  // namespace igms::devices::cerealbox
