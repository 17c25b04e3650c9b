// RunProgram: exit status, output captured to a file, and a program that does not exist.
#include "common/process/process.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace igms {
namespace {

std::string ReadAll(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(RunProgram, SucceedsWithStatusZero) { EXPECT_EQ(RunProgram({"true"}), ""); }

TEST(RunProgram, CapturesBothStreamsAndNamesTheFileOnFailure) {
  const auto log = std::filesystem::temp_directory_path() / "igms-process-test.log";
  const std::string error =
      RunProgram({"sh", "-c", "echo to-stdout; echo to-stderr >&2; exit 3"}, log.string());
  EXPECT_NE(error.find("exited with status 3"), std::string::npos) << error;
  EXPECT_NE(error.find(log.string()), std::string::npos) << error;
  const std::string text = ReadAll(log);
  EXPECT_NE(text.find("to-stdout"), std::string::npos);
  EXPECT_NE(text.find("to-stderr"), std::string::npos);
  std::filesystem::remove(log);
}

TEST(RunProgram, TextIsPassedAsAnArgumentNotThroughAShell) {
  const auto log = std::filesystem::temp_directory_path() / "igms-process-echo.log";
  EXPECT_EQ(RunProgram({"echo", "a; exit 7 $(false)"}, log.string()), "");
  EXPECT_EQ(ReadAll(log), "a; exit 7 $(false)\n");
  std::filesystem::remove(log);
}

TEST(RunProgram, AMissingProgramIsReported) {
  EXPECT_NE(RunProgram({"no-such-program-igms"}).find("cannot run"), std::string::npos);
  EXPECT_EQ(RunProgram({}), "no program to run");
}

}  // namespace
}  // namespace igms
