// The version the programs print and the servers report: CMake's project version, and the
// git revision of the checkout they were built from.
#include "common/version/version.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/child_process.h"

namespace igms::version {
namespace {

using igms::testing::BinDir;
using igms::testing::RunShell;
using igms::testing::SourceDir;

std::vector<std::string> Programs() {
  std::vector<std::string> out;
  std::stringstream list(IGMS_PROGRAMS);
  for (std::string name; std::getline(list, name, ',');) out.push_back(name);
  return out;
}

std::string Trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

// The checkout's commit, or "" when the sources are not a git checkout of their own.
std::string CheckoutCommit() {
  const std::string git = "git -C '" + SourceDir() + "' ";
  const auto top = RunShell(git + "rev-parse --show-toplevel 2>/dev/null");
  if (top.status != 0 || std::filesystem::weakly_canonical(Trimmed(top.out)) !=
                             std::filesystem::weakly_canonical(SourceDir())) {
    return "";
  }
  return Trimmed(RunShell(git + "rev-parse HEAD").out);
}

TEST(Version, IsTheProjectVersionAndTheCheckoutsRevision) {
  EXPECT_EQ(Project(), IGMS_TEST_PROJECT_VERSION);
  const std::string commit = CheckoutCommit();
  if (commit.empty()) {
    EXPECT_EQ(Revision(), "") << "built without a git checkout";
    EXPECT_EQ(Full(), Project());
    return;
  }
  const std::string revision(Revision());
  ASSERT_GE(revision.size(), 12u) << "'" << revision << "': no git revision in a git checkout";
  EXPECT_EQ(revision.substr(0, 12), commit.substr(0, 12))
      << "the build's revision is not the checkout's HEAD (rebuild after committing)";
  EXPECT_TRUE(revision.size() == 12 || revision.substr(12) == "-dirty") << revision;
  const std::string full = Full();
  EXPECT_EQ(full.rfind(std::string(Project()) + "+g" + commit.substr(0, 12), 0), 0u) << full;
}

TEST(Version, EveryProgramPrintsItsNameAndVersion) {
  const std::vector<std::string> programs = Programs();
  ASSERT_GE(programs.size(), 15u) << IGMS_PROGRAMS;
  for (const std::string& program : programs) {
    const auto run = RunShell("'" + BinDir() + "/" + program + "' --version 2>&1");
    EXPECT_EQ(run.status, 0) << program << ": " << run.out;
    EXPECT_EQ(run.out, Line(program) + "\n") << program;
  }
  // Through the lab's command too: `igms config --version` runs igms-config.
  EXPECT_EQ(RunShell("'" + BinDir() + "/igms' --version").out, Line("igms") + "\n");
  EXPECT_EQ(RunShell("'" + BinDir() + "/igms' config --version").out, Line("igms-config") + "\n");
}

}  // namespace
}  // namespace igms::version
