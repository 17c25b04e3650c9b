// The command layer and its input discipline: table 2.1's buttons held 100 ms on the
// readings' stamps, table 2.2's FlyBox on rising edges, table 2.4's voice codes only when new.
#include "control/session/inputs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace igms::control {
namespace {

constexpr int64_t kMs = 1'000'000;

// Feeds a viewer's readings every 14 ms (70 Hz) from `start` for `duration`; the commands.
std::vector<CommandKind> Hold(ViewerButtonFilter& f, bool left, bool right, int64_t start,
                              int64_t duration) {
  std::vector<CommandKind> out;
  for (int64_t t = start; t < start + duration; t += 14 * kMs)
    if (auto c = f.Feed(left, right, t)) out.push_back(*c);
  return out;
}

TEST(Commands, ViewerButtonsFollowTable21) {
  EXPECT_FALSE(CommandFromViewerButtons(false, false));
  EXPECT_EQ(CommandFromViewerButtons(false, true), CommandKind::kFreeze);
  EXPECT_EQ(CommandFromViewerButtons(true, false), CommandKind::kRange);
  EXPECT_EQ(CommandFromViewerButtons(true, true), CommandKind::kUnfreeze);
}

TEST(Commands, EveryVoiceCommandMapsToOneSessionCommand) {
  const std::pair<devices::VoiceCommand, CommandKind> table[] = {
      {devices::VOICE_FREEZE, CommandKind::kFreeze},
      {devices::VOICE_RANGE, CommandKind::kRange},
      {devices::VOICE_UNFREEZE, CommandKind::kUnfreeze},
      {devices::VOICE_BOX, CommandKind::kIdentifyBox},
      {devices::VOICE_CYLINDER, CommandKind::kIdentifyCylinder},
      {devices::VOICE_MARK, CommandKind::kMark},
      {devices::VOICE_UNMARK, CommandKind::kUnmark},
      {devices::VOICE_REMOVE_POINTS, CommandKind::kRemovePoints},
      {devices::VOICE_WIREFRAME, CommandKind::kWireframe},
      {devices::VOICE_SOLID, CommandKind::kSolid},
      {devices::VOICE_REMOVE_MODEL, CommandKind::kRemoveModel},
  };
  // Every value of the enum but UNSPECIFIED is in the table.
  const auto* descriptor = devices::VoiceCommand_descriptor();
  EXPECT_EQ(static_cast<size_t>(descriptor->value_count()), std::size(table) + 1);
  for (const auto& [voice, command] : table)
    EXPECT_EQ(CommandFromVoice(voice), command) << devices::VoiceCommand_Name(voice);
  EXPECT_FALSE(CommandFromVoice(devices::VOICE_COMMAND_UNSPECIFIED));
  EXPECT_FALSE(CommandFromVoice(static_cast<devices::VoiceCommand>(99)));
}

TEST(Commands, FlyBoxButtonsFollowTable22) {
  EXPECT_EQ(CommandFromJoystickButton(1), CommandKind::kUnmark);
  EXPECT_EQ(CommandFromJoystickButton(2), CommandKind::kToggleWireframe);
  EXPECT_EQ(CommandFromJoystickButton(3), CommandKind::kRemoveModel);
  for (int b = 4; b <= 8; ++b) EXPECT_FALSE(CommandFromJoystickButton(b)) << b;
  EXPECT_EQ(kJoystickTriggerCommand, CommandKind::kMark);
}

TEST(ViewerButtons, ActOnceWhenHeld100Ms) {
  ViewerButtonFilter f(100 * kMs);
  // Readings at 0, 14, ..., 98 ms do not act; the one at 112 ms does; holding does not repeat.
  EXPECT_TRUE(Hold(f, false, true, 0, 100 * kMs).empty());
  EXPECT_EQ(f.Feed(false, true, 112 * kMs), CommandKind::kFreeze);
  EXPECT_TRUE(Hold(f, false, true, 126 * kMs, 2000 * kMs).empty());
}

TEST(ViewerButtons, ExactlyTheHoldTimeActs) {
  ViewerButtonFilter f(100 * kMs);
  EXPECT_FALSE(f.Feed(true, false, 5 * kMs));
  EXPECT_FALSE(f.Feed(true, false, 104 * kMs));
  EXPECT_EQ(f.Feed(true, false, 105 * kMs), CommandKind::kRange);
}

TEST(ViewerButtons, PassingThrough01OnTheWayTo11DoesNotFreeze) {
  ViewerButtonFilter f(100 * kMs);
  // The right button lands 56 ms before the left: 01 for four readings, then 11 held.
  EXPECT_TRUE(Hold(f, false, true, 0, 56 * kMs).empty());
  const auto commands = Hold(f, true, true, 56 * kMs, 500 * kMs);
  EXPECT_EQ(commands, std::vector<CommandKind>{CommandKind::kUnfreeze});
  // Letting go passes through 10 (a range) and 00: neither acts.
  EXPECT_TRUE(Hold(f, true, false, 556 * kMs, 42 * kMs).empty());
  EXPECT_TRUE(Hold(f, false, false, 598 * kMs, 1000 * kMs).empty());
}

TEST(ViewerButtons, ReleasedAndPressedAgainActsAgain) {
  ViewerButtonFilter f(100 * kMs);
  EXPECT_EQ(Hold(f, false, true, 0, 200 * kMs).size(), 1u);
  EXPECT_TRUE(Hold(f, false, false, 200 * kMs, 100 * kMs).empty());
  EXPECT_EQ(Hold(f, false, true, 300 * kMs, 200 * kMs).size(), 1u);
}

TEST(ViewerButtons, StampsGoingBackStartTheHoldAgain) {
  ViewerButtonFilter f(100 * kMs);
  EXPECT_FALSE(f.Feed(false, true, 1000 * kMs));
  // A restarted daemon's clock: the hold is measured from here.
  EXPECT_FALSE(f.Feed(false, true, 10 * kMs));
  EXPECT_FALSE(f.Feed(false, true, 100 * kMs));
  EXPECT_EQ(f.Feed(false, true, 110 * kMs), CommandKind::kFreeze);
}

TEST(StampTime, DeviceClockWhereThereIsOne) {
  devices::Stamp s;
  s.set_receive_monotonic_ns(5'000);
  EXPECT_EQ(StampTimeNs(s), 5'000);
  s.set_device_time_us(7);
  EXPECT_EQ(StampTimeNs(s), 7'000);
}

devices::JoystickState Stick(double x, double y, double twist, uint32_t buttons, bool trigger,
                             int64_t t_ns) {
  devices::JoystickState s;
  s.set_x(x);
  s.set_y(y);
  s.set_twist(twist);
  s.set_buttons(buttons);
  s.set_trigger(trigger);
  s.mutable_stamp()->set_receive_monotonic_ns(t_ns);
  return s;
}

TEST(Joystick, ButtonsActOnPressNotWhileHeld) {
  JoystickMapper m(0.05);
  EXPECT_TRUE(m.Feed(Stick(0, 0, 0, 0, false, 0)).commands.empty());
  EXPECT_EQ(m.Feed(Stick(0, 0, 0, 0, true, 20 * kMs)).commands,
            std::vector<CommandKind>{CommandKind::kMark});
  EXPECT_TRUE(m.Feed(Stick(0, 0, 0, 0, true, 40 * kMs)).commands.empty());
  EXPECT_TRUE(m.Feed(Stick(0, 0, 0, 0, false, 60 * kMs)).commands.empty());
  EXPECT_EQ(m.Feed(Stick(0, 0, 0, 0, true, 80 * kMs)).commands,
            std::vector<CommandKind>{CommandKind::kMark});
  // Buttons 1, 2, 3 pressed together, with 4-8: three commands in button order.
  EXPECT_EQ(m.Feed(Stick(0, 0, 0, 0xFF, true, 100 * kMs)).commands,
            (std::vector<CommandKind>{CommandKind::kUnmark, CommandKind::kToggleWireframe,
                                      CommandKind::kRemoveModel}));
  EXPECT_TRUE(m.Feed(Stick(0, 0, 0, 0xFF, true, 120 * kMs)).commands.empty());
}

TEST(Joystick, TheFirstReadingOfASubscriptionIsABaseline) {
  JoystickMapper m(0.05);
  // Held while the joystick (re)connected: not a press.
  EXPECT_TRUE(m.Feed(Stick(0, 0, 0, 0x1, true, 0)).commands.empty());
  EXPECT_TRUE(m.Feed(Stick(0, 0, 0, 0x1, true, 20 * kMs)).commands.empty());
  m.Reset();
  EXPECT_TRUE(m.Feed(Stick(0, 0, 0, 0x5, true, 40 * kMs)).commands.empty());
  EXPECT_EQ(m.Feed(Stick(0, 0, 0, 0x7, true, 60 * kMs)).commands,
            std::vector<CommandKind>{CommandKind::kToggleWireframe});
}

TEST(Joystick, AxesDriveThePointerWithADeadBand) {
  JoystickMapper m(0.05);
  const PointerDrive d = m.Feed(Stick(0.5, -0.25, 1.0, 0, false, 123 * kMs)).drive;
  EXPECT_DOUBLE_EQ(d.forward, 0.5);  // x: forward/backward
  EXPECT_DOUBLE_EQ(d.right, -0.25);  // y: left/right
  EXPECT_DOUBLE_EQ(d.up, 1.0);       // twist
  EXPECT_EQ(d.time_ns, 123 * kMs);
  // The FlyBox's centre (2048 of 4095) and a worn stick read as still; NaN as nothing.
  const PointerDrive still = m.Feed(Stick(0.00024, -0.049, NAN, 0, false, 0)).drive;
  EXPECT_EQ(still.forward, 0.0);
  EXPECT_EQ(still.right, 0.0);
  EXPECT_EQ(still.up, 0.0);
}

devices::VoiceState Voice(devices::VoiceCommand c, uint64_t sequence) {
  devices::VoiceState v;
  v.set_command(c);
  v.mutable_stamp()->set_sequence(sequence);
  return v;
}

TEST(Voice, OnlyNewEventsAfterSubscribingAct) {
  VoiceFilter f;
  // Not subscribed yet: nothing acts.
  EXPECT_FALSE(f.Feed(Voice(devices::VOICE_FREEZE, 3)));
  // The daemon had heard 3 commands; the newest (3) is sent first on subscribing: old news.
  f.Subscribed(3);
  EXPECT_FALSE(f.Feed(Voice(devices::VOICE_FREEZE, 3)));
  EXPECT_EQ(f.Feed(Voice(devices::VOICE_MARK, 4)), CommandKind::kMark);
  EXPECT_FALSE(f.Feed(Voice(devices::VOICE_MARK, 4)));  // the same event again
  EXPECT_FALSE(f.Feed(Voice(devices::VOICE_MARK, 2)));  // an older one
  EXPECT_EQ(f.Feed(Voice(devices::VOICE_UNMARK, 6)), CommandKind::kUnmark);
  EXPECT_FALSE(f.Feed(Voice(devices::VOICE_COMMAND_UNSPECIFIED, 7)));
  // A restarted daemon counts from 1 again; the new subscription says where it stands.
  f.Subscribed(0);
  EXPECT_EQ(f.Feed(Voice(devices::VOICE_FREEZE, 1)), CommandKind::kFreeze);
}

}  // namespace
}  // namespace igms::control
