// igms-voice-decode as a process: sound files and state switches in, two-digit codes out.
// (The daemon, igms-voiced, is tested in voice_daemon_test.cpp.)
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

#include "tests/support/child_process.h"
#include "tests/support/files.h"

namespace {

std::string Bin() { return igms::testing::BinDir() + "/igms-voice-decode"; }

using Result = igms::testing::ShellRun;

// The program's log (stderr) is dropped: stdout carries the codes alone.
Result Exec(const std::string& command) {
  return igms::testing::RunShell(command + " 2>/dev/null");
}

class VoiceDecodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = igms::testing::FreshTempDir("voice-decode");
    for (const char* word : {"freeze", "box", "unfreeze"}) {
      const std::string path = (dir_ / (std::string(word) + ".wav")).string();
      ASSERT_EQ(Exec("espeak-ng -v en-us -w " + path + " " + word).status, 0);
    }
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string F(const char* word) { return (dir_ / (std::string(word) + ".wav")).string(); }
  std::filesystem::path dir_;
};

TEST_F(VoiceDecodeTest, PrintsCodesAndFollowsStateSwitches) {
  // freeze moves to model building by itself; box is not valid there; after the
  // control client's "awaiting_type" it is; unfreeze then returns to verification.
  const Result run = Exec(Bin() + " " + F("freeze") + " " + F("box") + " state=awaiting_type " +
                          F("box") + " " + F("unfreeze"));
  EXPECT_EQ(run.status, 0);
  EXPECT_EQ(run.out, "01\n10\n03\n");
}

TEST_F(VoiceDecodeTest, BadInputIsAnErrorNotACrash) {
  EXPECT_EQ(Exec(Bin() + " /nonexistent.wav").status, 1);
  EXPECT_EQ(Exec(Bin() + " state=frozen " + F("freeze")).status, 2);
  EXPECT_EQ(Exec(Bin()).status, 2);
  EXPECT_EQ(Exec(Bin() + " --model-dir /nonexistent " + F("freeze")).status, 2);
  EXPECT_EQ(Exec(Bin() + " --min-confidence 7 " + F("freeze")).status, 2);
}

TEST_F(VoiceDecodeTest, NoMicrophoneHereIsReportedClearly) {
  // The machine has no capture device: the program must say so and exit, not hang.
  const Result run = Exec("ALSOFT_DRIVERS=null timeout 20 " + Bin() + " --mic");
  EXPECT_EQ(run.status, 1);
}

}  // namespace
