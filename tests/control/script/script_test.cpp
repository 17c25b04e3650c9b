// The operator script's language (docs/scripts.md): every action read as written, and every
// mistake refused with the file and line it is on, before anything is played.
#include "control/script/script.h"

#include <gtest/gtest.h>

namespace igms::control {
namespace {

Script Parsed(const std::string& text) {
  auto script = ParseScript(text, "s.yaml");
  EXPECT_TRUE(script.ok()) << script.error();
  return script.ok() ? *script : Script{};
}

std::string ErrorOf(const std::string& text) {
  auto script = ParseScript(text, "s.yaml");
  EXPECT_FALSE(script.ok()) << text;
  return script.ok() ? "" : script.error();
}

TEST(Script, EveryActionIsReadAsWritten) {
  const Script s = Parsed(
      "- look: {yaw: 12.5, pitch: -3, roll: 1}\n"
      "- button: freeze\n"
      "- move_to: [4.2, -1.0, 61.3]\n"
      "- move_to: {point: [1, 2, 3], tolerance: 0.5, timeout: 9}\n"
      "- trigger\n"
      "- stick: {x: 0.25, y: -1, twist: 0.5, seconds: 0.4}\n"
      "- joystick_button: 3\n"
      "- range\n"
      "- say: cylinder\n"
      "- fault: {device: joystick, garbage_bytes: 40}\n"
      "- wait_for: {mode: model_building, timeout: 20}\n"
      "- wait_for: {models: 2}\n"
      "- screenshot: overlay.png\n");
  ASSERT_EQ(s.actions.size(), 13u);
  EXPECT_EQ(s.actions[0].kind, ActionKind::kLook);
  EXPECT_DOUBLE_EQ(s.actions[0].yaw, 12.5);
  EXPECT_DOUBLE_EQ(s.actions[0].pitch, -3);
  EXPECT_EQ(s.actions[1].kind, ActionKind::kButton);
  EXPECT_EQ(s.actions[2].point, Eigen::Vector3d(4.2, -1.0, 61.3));
  EXPECT_DOUBLE_EQ(s.actions[2].tolerance, 0.02);
  EXPECT_DOUBLE_EQ(s.actions[3].tolerance, 0.5);
  EXPECT_DOUBLE_EQ(s.actions[3].timeout_s, 9);
  EXPECT_EQ(s.actions[4].kind, ActionKind::kTrigger);
  EXPECT_DOUBLE_EQ(s.actions[5].y, -1);
  EXPECT_DOUBLE_EQ(s.actions[5].seconds, 0.4);
  EXPECT_EQ(s.actions[6].joystick_button, 3);
  EXPECT_EQ(s.actions[7].kind, ActionKind::kRange);
  EXPECT_EQ(s.actions[8].phrase, "cylinder");
  EXPECT_EQ(s.actions[9].device, "joystick");
  EXPECT_EQ(s.actions[10].mode, "model building");
  EXPECT_DOUBLE_EQ(s.actions[10].timeout_s, 20);
  EXPECT_EQ(s.actions[11].models, 2);
  EXPECT_EQ(s.actions[12].file, "overlay.png");
  for (size_t i = 0; i < s.actions.size(); ++i) EXPECT_EQ(s.actions[i].line, int(i) + 1);
}

TEST(Script, AnEmptyScriptDoesNothing) { EXPECT_TRUE(Parsed("").actions.empty()); }

TEST(Script, MistakesNameTheirLine) {
  EXPECT_NE(ErrorOf("- trigger\n- jump: 3\n").find("s.yaml:2: unknown action 'jump'"),
            std::string::npos);
  EXPECT_NE(ErrorOf("- trigger\n- range\n- look: {yaw: 400}\n").find("s.yaml:3:"),
            std::string::npos);
  EXPECT_NE(ErrorOf("- stick: {x: 2}\n").find("s.yaml:1:"), std::string::npos);
  EXPECT_NE(ErrorOf("- joystick_button: 9\n").find("button 1-8"), std::string::npos);
  EXPECT_NE(ErrorOf("- trigger: now\n").find("takes no value"), std::string::npos);
  EXPECT_NE(ErrorOf("- say: \"\"\n").find("needs a phrase"), std::string::npos);
  EXPECT_NE(ErrorOf("- move_to: {point: [1, 2, 3], tolerance: -1}\n").find("tolerance"),
            std::string::npos);
  EXPECT_NE(ErrorOf("- wait_for: {models: 1, timeout: 0}\n").find("positive"), std::string::npos);
  EXPECT_NE(ErrorOf("look: {yaw: 1}\n").find("a list of actions"), std::string::npos);
  EXPECT_NE(ErrorOf("- [unclosed\n").find("s.yaml:"), std::string::npos);
}

TEST(Script, NumbersMustBeNumbers) {
  EXPECT_NE(ErrorOf("- look: {yaw: .nan}\n").find("s.yaml:1"), std::string::npos);
  EXPECT_NE(ErrorOf("- move_to: [1, two, 3]\n").find("s.yaml:1"), std::string::npos);
}

TEST(Script, AMissingFileIsNamed) {
  auto script = LoadScript("/nonexistent/session.yaml");
  ASSERT_FALSE(script.ok());
  EXPECT_NE(script.error().find("/nonexistent/session.yaml"), std::string::npos);
}

}  // namespace
}  // namespace igms::control
