// The Dragon Writer line: the byte-fed parsers, the simulator, and the driver against the
// simulator over a real pseudo-terminal.
#include <gtest/gtest.h>

#include "common/base/clock.h"
#include "device_daemons/serial/pty_host.h"
#include "device_daemons/voice/dragon_driver.h"
#include "device_daemons/voice/dragon_protocol.h"
#include "device_daemons/voice/dragon_sim.h"
#include "device_daemons/voice/voice_proto.h"
#include "tests/support/files.h"
#include "tests/support/io_thread.h"
#include "tests/support/readings.h"
#include "tests/support/wait_for.h"

namespace igms::voice {
namespace {

using devices::ParseResult;

std::vector<dragon::Report> ParseAll(dragon::ReportParser& p, std::string_view bytes) {
  std::vector<dragon::Report> out;
  for (char c : bytes) {
    if (p.Feed(static_cast<uint8_t>(c)) == ParseResult::kGood) out.push_back(p.report());
  }
  return out;
}

TEST(DragonProtocol, EveryCodeRoundTripsInThreeBytes) {
  for (const CommandInfo& info : AllCommands()) {
    const std::string bytes = dragon::EncodeCommand(info.command);
    EXPECT_EQ(bytes, std::string(info.code) + "\r");
    dragon::ReportParser p;
    const auto got = ParseAll(p, bytes);
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0].command, info.command);
    EXPECT_EQ(static_cast<int>(ToProto(info.command)), std::stoi(std::string(info.code)));
    EXPECT_EQ(FromProto(ToProto(info.command)), info.command);
  }
  // Table 2.4's codes.
  EXPECT_EQ(dragon::EncodeCommand(Command::kFreeze), "01\r");
  EXPECT_EQ(dragon::EncodeCommand(Command::kRange), "02\r");
  EXPECT_EQ(dragon::EncodeCommand(Command::kUnfreeze), "03\r");
  EXPECT_EQ(dragon::EncodeCommand(Command::kBox), "10\r");
  EXPECT_EQ(dragon::EncodeCommand(Command::kCylinder), "11\r");
  dragon::ReportParser p;
  const auto alive = ParseAll(p, dragon::EncodeAlive() + "\n");  // CR LF is one line end
  ASSERT_EQ(alive.size(), 1u);
  EXPECT_FALSE(alive[0].command);
  EXPECT_EQ(p.bad_frames(), 0u);
}

TEST(DragonProtocol, ResynchronisesAfterGarbageAndCountsIt) {
  dragon::ReportParser p;
  // Garbage glued to the front of a code, a line with no code, an unknown code, a lone
  // digit, a long run without a line end: each costs only itself.
  const std::string stream = std::string("\xff\x13zz9") + "10\r" + "hello\r" + "45\r" + "7\r" +
                             std::string(1000, 'x') + "\r" + "01\r" + "\r\n" + "32\n";
  const auto got = ParseAll(p, stream);
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[0].command, Command::kBox);
  EXPECT_EQ(got[1].command, Command::kFreeze);
  EXPECT_EQ(got[2].command, Command::kRemoveModel);
  EXPECT_EQ(p.bad_frames(), 4u);               // hello, 45, 7, xxx...
  EXPECT_EQ(p.garbage_bytes(), 5u + 3 + 998);  // bytes pushed out ahead of a line's last two
  EXPECT_EQ(p.good_frames(), 3u);
}

TEST(DragonProtocol, BareDigitPairsAreTakenWhenTheLineGoesQuiet) {
  dragon::ReportParser p;
  for (char c : std::string("x10"))
    EXPECT_EQ(p.Feed(static_cast<uint8_t>(c)), ParseResult::kNeedMore);
  ASSERT_EQ(p.Idle(), ParseResult::kGood);
  EXPECT_EQ(p.report().command, Command::kBox);
  EXPECT_EQ(p.Idle(), ParseResult::kNeedMore);  // taken once
  // The CR of a code split by a pause is then an empty line, not a second report.
  EXPECT_EQ(p.Feed('\r'), ParseResult::kNeedMore);
  // Half a code, or no code, waits for more.
  p.Feed('0');
  EXPECT_EQ(p.Idle(), ParseResult::kNeedMore);
  EXPECT_EQ(p.Feed('3'), ParseResult::kNeedMore);
  ASSERT_EQ(p.Idle(), ParseResult::kGood);
  EXPECT_EQ(p.report().command, Command::kUnfreeze);
  p.Feed('4');
  p.Feed('5');
  EXPECT_EQ(p.Idle(), ParseResult::kNeedMore);
  EXPECT_EQ(p.Feed('\r'), ParseResult::kBad);
}

TEST(DragonProtocol, HostRequests) {
  dragon::HostParser p;
  std::vector<dragon::HostRequest> got;
  const std::string stream =
      dragon::EncodeProbe() + dragon::EncodeSetState(OperatorState::kAwaitingType) + "S9\r" +
      "junk?\r" + "\n" + dragon::EncodeSetState(OperatorState::kVerification);
  for (char c : stream) {
    if (p.Feed(static_cast<uint8_t>(c)) == ParseResult::kGood) got.push_back(p.request());
  }
  ASSERT_EQ(got.size(), 4u);
  EXPECT_TRUE(got[0].probe);
  EXPECT_EQ(got[1].state, OperatorState::kAwaitingType);
  EXPECT_TRUE(got[2].probe);  // "junk?": the probe at the end of the line
  EXPECT_EQ(got[3].state, OperatorState::kVerification);
  EXPECT_EQ(p.bad_frames(), 1u);  // S9
}

TEST(DragonSim, HearsOnlyTheWordsOfItsStateAndFollowsTheHost) {
  DragonSim sim;
  EXPECT_EQ(sim.Say("unfreeze", 0), Heard::kNotValidInState);  // the thesis's flaw
  EXPECT_EQ(sim.Say("hello", 0), Heard::kNotACommand);
  // The host says the system froze (the BOOM's button): now unfreeze is heard.
  auto out = sim.OnInput(dragon::EncodeSetState(OperatorState::kModelBuilding), 0);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0], "00\r");
  EXPECT_EQ(sim.Say("  Unfreeze ", 1000), Heard::kSent);
  EXPECT_EQ(sim.state(), OperatorState::kVerification);  // its own prediction
  int64_t wake = INT64_MAX;
  EXPECT_TRUE(sim.Poll(1000, &wake).empty());
  EXPECT_EQ(wake, 1000 + DragonSimOptions().recognition_ns);
  out = sim.Poll(wake, &wake);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0], "03\r");
  EXPECT_EQ(sim.sent(), 1u);
  EXPECT_EQ(sim.not_heard(), 2u);
}

TEST(DragonPty, CodesArriveStateFollowsAndGarbageIsSurvived) {
  auto sim = std::make_unique<DragonSim>();
  DragonSim* raw = sim.get();
  devices::PtyHost host(std::move(sim), {igms::testing::TempPath("dragon"), 9600});
  std::string error;
  ASSERT_TRUE(host.Start(&error)) << error;
  igms::testing::IoThread io;
  igms::testing::Collected<devices::VoiceState> got;
  devices::SerialLinkOptions link;
  link.port = host.port();
  link.silence_timeout = std::chrono::milliseconds(600);
  DragonDriver driver(io.io(), link, OperatorState::kVerification,
                      [&](const devices::VoiceState& s) { got.Add(s); });
  driver.Start();
  ASSERT_TRUE(igms::testing::WaitFor(
      "the link up", [&] { return driver.status().state() == devices::CONNECTED; }));
  const auto say = [&](const std::string& phrase) {
    host.WithDevice([&](devices::SimulatedDevice&) { raw->Say(phrase, igms::MonotonicNs()); });
  };
  say("freeze");
  ASSERT_TRUE(igms::testing::WaitFor("the first code", [&] { return got.size() == 1; }));
  devices::VoiceState s = got.last();
  EXPECT_EQ(s.command(), devices::VOICE_FREEZE);
  EXPECT_EQ(s.text(), "freeze");
  EXPECT_EQ(s.state(), devices::VERIFICATION);
  EXPECT_EQ(s.stamp().sequence(), 1u);
  EXPECT_GT(s.stamp().receive_unix_ns(), 0);
  EXPECT_EQ(driver.state(), OperatorState::kModelBuilding);  // predicted after freeze

  // The control client says the object type is awaited: both ends follow.
  driver.SetState(OperatorState::kAwaitingType);
  ASSERT_TRUE(igms::testing::WaitFor("the recogniser awaiting the type", [&] {
    OperatorState st{};
    host.WithDevice([&](devices::SimulatedDevice&) { st = raw->state(); });
    return st == OperatorState::kAwaitingType;
  }));
  // The next probe answer ("00") is cut short: its half runs into the answer after it, whose
  // line then starts with a byte too many, counted as garbage. Then a burst of garbage.
  const uint64_t garbage_before = driver.status().garbage_bytes();
  host.TruncateNext();
  ASSERT_TRUE(igms::testing::WaitFor("the cut probe answer counted as garbage", [&] {
    return driver.status().garbage_bytes() > garbage_before;
  }));
  host.InjectGarbage(200);
  say("cylinder");
  ASSERT_TRUE(igms::testing::WaitFor("the code after the garbage", [&] {
    return got.size() >= 2 && got.last().command() == devices::VOICE_CYLINDER;
  }));
  const devices::LinkStatus status = driver.status();
  EXPECT_GT(status.garbage_bytes() + status.bad_frames(), 0u);
  EXPECT_EQ(status.state(), devices::CONNECTED);
  driver.Stop();
  io.Stop();
}

}  // namespace
}  // namespace igms::voice
