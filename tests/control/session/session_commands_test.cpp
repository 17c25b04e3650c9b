// Commands by voice and by the fly box's buttons, and which commands each mode accepts.
#include "tests/control/session/session_fixture.h"

namespace igms::control {
namespace {

// ---- voice ----

TEST_F(SessionTest, VoiceActsOnlyWhenNewAndValid) {
  Start();
  // Before subscribing, and the newest command sent on subscribing, do nothing.
  EXPECT_TRUE(Voice(devices::VOICE_FREEZE, 7).empty());
  Send(VoiceSubscribed{7, now_});
  EXPECT_TRUE(Voice(devices::VOICE_FREEZE, 7).empty());
  EXPECT_EQ(session_->mode(), Mode::kVerification);
  // Not valid in verification: refused, said on the display only.
  Effects e = Voice(devices::VOICE_MARK, 8);
  EXPECT_FALSE(Has<PlaySoundEffect>(e));
  EXPECT_NE(Notices(e).find("mark (voice) is not valid while verification"), std::string::npos);
  e = Voice(devices::VOICE_FREEZE, 9);
  EXPECT_EQ(session_->mode(), Mode::kFreezing);
  // The same event delivered twice does not act twice.
  EXPECT_TRUE(Voice(devices::VOICE_FREEZE, 9).empty());
}

TEST_F(SessionTest, TheFlyBoxButtonsFollowTable22) {
  Start();
  FreezeAndGrab();
  Joystick(0, 0, 0, 0, false);
  // Button 2: wireframe, and again solid.
  Effects e = Joystick(0, 0, 0, 0x2, false);
  ASSERT_EQ(All<DisplayEffect>(e).size(), 1u);
  EXPECT_TRUE(All<DisplayEffect>(e)[0].wireframe);
  Joystick(0, 0, 0, 0, false);
  e = Joystick(0, 0, 0, 0x2, false);
  EXPECT_FALSE(All<DisplayEffect>(e)[0].wireframe);
  // Voice wireframe and solid set it; saying it twice changes nothing.
  EXPECT_TRUE(All<DisplayEffect>(Command(CommandKind::kWireframe))[0].wireframe);
  EXPECT_FALSE(Has<DisplayEffect>(Command(CommandKind::kWireframe)));
  EXPECT_FALSE(All<DisplayEffect>(Command(CommandKind::kSolid))[0].wireframe);
}

TEST(SessionHelpers, FailureMessagesAreFoundByTheReasonsEnumName) {
  sound::ListBankResponse bank;
  auto* a = bank.add_sounds();
  a->set_key("not_found_degenerate_marks");
  a->set_reason("FAILURE_MARKS_DEGENERATE");
  auto* b = bank.add_sounds();
  b->set_key("welcome");
  EXPECT_EQ(FailureMessageKey(bank, object::FAILURE_MARKS_DEGENERATE),
            "not_found_degenerate_marks");
  EXPECT_EQ(FailureMessageKey(bank, object::FAILURE_FIT_FAILED), "");
}

TEST(SessionHelpers, ValidCommandsFollowTheVoiceGrammars) {
  // docs/voice.md's words per state are valid in the session's matching modes.
  using C = CommandKind;
  for (C c : {C::kFreeze, C::kWireframe, C::kSolid, C::kRemoveModel})
    EXPECT_TRUE(IsValid(Mode::kVerification, c)) << CommandName(c);
  for (C c : {C::kUnfreeze, C::kRange, C::kMark, C::kUnmark, C::kRemovePoints, C::kWireframe,
              C::kSolid, C::kRemoveModel})
    EXPECT_TRUE(IsValid(Mode::kModelBuilding, c)) << CommandName(c);
  for (C c : {C::kIdentifyBox, C::kIdentifyCylinder, C::kUnmark, C::kRemovePoints, C::kUnfreeze})
    EXPECT_TRUE(IsValid(Mode::kAwaitingType, c)) << CommandName(c);
  for (C c : {C::kUnfreeze, C::kRange, C::kMark, C::kIdentifyBox})
    EXPECT_FALSE(IsValid(Mode::kVerification, c)) << CommandName(c);
  for (C c : {C::kFreeze, C::kIdentifyBox}) EXPECT_FALSE(IsValid(Mode::kModelBuilding, c));
  for (C c : {C::kFreeze, C::kMark, C::kRange}) EXPECT_FALSE(IsValid(Mode::kAwaitingType, c));
  EXPECT_FALSE(IsValid(Mode::kStarting, C::kFreeze));
  EXPECT_EQ(OperatorStateOf(Mode::kLocating), devices::MODEL_BUILDING);
}

}  // namespace
}  // namespace igms::control
