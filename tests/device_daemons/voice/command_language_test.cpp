#include "device_daemons/voice/command_language.h"

#include <gtest/gtest.h>

#include <set>

namespace igms::voice {
namespace {

TEST(CommandLanguage, KeepsTheThesisCodesOfTable24) {
  EXPECT_EQ(Code(Command::kFreeze), "01");
  EXPECT_EQ(Code(Command::kRange), "02");
  EXPECT_EQ(Code(Command::kUnfreeze), "03");
  EXPECT_EQ(Code(Command::kBox), "10");
  EXPECT_EQ(Code(Command::kCylinder), "11");
}

TEST(CommandLanguage, CodesArePairsOfDigitsAndRoundTrip) {
  std::set<std::string_view> codes, phrases;
  for (const CommandInfo& info : AllCommands()) {
    ASSERT_EQ(info.code.size(), 2u);
    EXPECT_TRUE(std::isdigit(info.code[0]) && std::isdigit(info.code[1])) << info.code;
    EXPECT_TRUE(codes.insert(info.code).second) << "duplicate code " << info.code;
    EXPECT_TRUE(phrases.insert(info.phrase).second) << "duplicate phrase " << info.phrase;
    EXPECT_EQ(CommandFromCode(info.code), info.command);
    EXPECT_EQ(CommandFromPhrase(info.phrase), info.command);
  }
  EXPECT_EQ(AllCommands().size(), 11u);
}

// The numbers of igms.devices.VoiceCommand, which the daemon publishes.
TEST(CommandLanguage, NewCodesMatchTheDevicesProtocol) {
  EXPECT_EQ(Code(Command::kMark), "20");
  EXPECT_EQ(Code(Command::kUnmark), "21");
  EXPECT_EQ(Code(Command::kRemovePoints), "22");
  EXPECT_EQ(Code(Command::kWireframe), "30");
  EXPECT_EQ(Code(Command::kSolid), "31");
  EXPECT_EQ(Code(Command::kRemoveModel), "32");
}

TEST(CommandLanguage, ListsAreInCodeOrder) {
  for (size_t i = 1; i < AllCommands().size(); ++i) {
    EXPECT_LT(AllCommands()[i - 1].code, AllCommands()[i].code);
  }
  for (OperatorState s : AllStates()) {
    const auto valid = ValidCommands(s);
    for (size_t i = 1; i < valid.size(); ++i) EXPECT_LT(Code(valid[i - 1]), Code(valid[i]));
  }
}

TEST(CommandLanguage, RejectsAnythingElse) {
  EXPECT_FALSE(CommandFromCode("1"));
  EXPECT_FALSE(CommandFromCode("99"));
  EXPECT_FALSE(CommandFromCode(""));
  EXPECT_FALSE(CommandFromPhrase("freezer"));
  EXPECT_FALSE(CommandFromPhrase("remove"));
  EXPECT_EQ(CommandFromPhrase("  Remove   POINTS "), Command::kRemovePoints);
}

TEST(CommandLanguage, StatesFollowSections216And24) {
  EXPECT_TRUE(IsValid(OperatorState::kVerification, Command::kFreeze));
  EXPECT_TRUE(IsValid(OperatorState::kVerification, Command::kWireframe));
  EXPECT_FALSE(IsValid(OperatorState::kVerification, Command::kUnfreeze));
  EXPECT_FALSE(IsValid(OperatorState::kVerification, Command::kMark));
  EXPECT_TRUE(IsValid(OperatorState::kModelBuilding, Command::kRange));
  EXPECT_TRUE(IsValid(OperatorState::kModelBuilding, Command::kMark));
  EXPECT_FALSE(IsValid(OperatorState::kModelBuilding, Command::kFreeze));
  EXPECT_FALSE(IsValid(OperatorState::kModelBuilding, Command::kBox));
  EXPECT_TRUE(IsValid(OperatorState::kAwaitingType, Command::kBox));
  EXPECT_TRUE(IsValid(OperatorState::kAwaitingType, Command::kCylinder));
  EXPECT_FALSE(IsValid(OperatorState::kAwaitingType, Command::kMark));
  // Every command is valid somewhere.
  for (const CommandInfo& info : AllCommands()) {
    bool somewhere = false;
    for (OperatorState s : AllStates()) somewhere |= IsValid(s, info.command);
    EXPECT_TRUE(somewhere) << info.phrase;
  }
}

TEST(CommandLanguage, PredictsTheObviousNextState) {
  using S = OperatorState;
  EXPECT_EQ(PredictNextState(S::kVerification, Command::kFreeze), S::kModelBuilding);
  EXPECT_EQ(PredictNextState(S::kModelBuilding, Command::kUnfreeze), S::kVerification);
  EXPECT_EQ(PredictNextState(S::kAwaitingType, Command::kBox), S::kModelBuilding);
  EXPECT_EQ(PredictNextState(S::kAwaitingType, Command::kUnmark), S::kModelBuilding);
  EXPECT_EQ(PredictNextState(S::kModelBuilding, Command::kMark), S::kModelBuilding);
  // An invalid command changes nothing.
  EXPECT_EQ(PredictNextState(S::kVerification, Command::kUnfreeze), S::kVerification);
}

TEST(CommandLanguage, StateNamesRoundTrip) {
  for (OperatorState s : AllStates()) EXPECT_EQ(StateFromName(StateName(s)), s);
  EXPECT_EQ(StateFromName("building"), OperatorState::kModelBuilding);
  EXPECT_EQ(StateFromName("type"), OperatorState::kAwaitingType);
  EXPECT_FALSE(StateFromName("frozen"));
}

}  // namespace
}  // namespace igms::voice
