// The configuration check against the real programs: PROGRAM --check-config, `igms config
// check` over every process of a lab file, unknown keys refused at start (or allowed), and
// lab.log_level applied under the process's own level.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <string>

#include "igms/common.pb.h"
#include "tests/support/child_process.h"

namespace igms {
namespace {

using namespace std::chrono_literals;
using testing::BinDir;
using testing::RunShell;
using testing::ScratchDir;
using testing::SourceDir;

void Write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string Replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "no '" << from << "' to replace";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// deploy/lab.yaml, copied where its relative calibration path would not reach.
std::string DeployLabWithAbsolutePaths() {
  return Replaced(Read(SourceDir() + "/deploy/lab.yaml"),
                  "../common/calibration/data/thesis_calibration.yaml",
                  testing::ThesisCalibration());
}

const char* kPlatformLab =
    "lab:\n"
    "  log_level: info\n"
    "processes:\n"
    "  platform:\n"
    "    program: igms-platformd\n"
    "    port: 0\n"
    "    serial: simulate\n"
    "    poll_hz: 20\n";

TEST(CheckConfig, AGoodFilePassesAndStartsNothing) {
  ScratchDir dir;
  Write(dir.File("lab.yaml"), kPlatformLab);
  const auto r = RunShell(BinDir() + "/igms-platformd --check-config --config " +
                          dir.File("lab.yaml") + " --name platform 2>&1");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out, dir.File("lab.yaml") + ": OK for processes.platform\n");
}

TEST(CheckConfig, ATypoFailsNamingTheLineAndTheIntendedKey) {
  ScratchDir dir;
  Write(dir.File("lab.yaml"), Replaced(kPlatformLab, "poll_hz: 20", "poll_hx: 20"));
  const auto r = RunShell(BinDir() + "/igms-platformd --check-config --config " +
                          dir.File("lab.yaml") + " --name platform 2>&1");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find(dir.File("lab.yaml") + ":8: unknown key processes.platform.poll_hx (did "
                                              "you mean processes.platform.poll_hz?)"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("OK"), std::string::npos) << r.out;
}

TEST(CheckConfig, ABadValueFailsNamingIt) {
  ScratchDir dir;
  Write(dir.File("lab.yaml"), Replaced(kPlatformLab, "poll_hz: 20", "poll_hz: fast"));
  const auto r = RunShell(BinDir() + "/igms-platformd --check-config --config " +
                          dir.File("lab.yaml") + " --name platform 2>&1");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find(":8: processes.platform.poll_hz must be a number (found 'fast')"),
            std::string::npos)
      << r.out;
  // A value the component's own validation refuses (two sources) fails the check too.
  Write(dir.File("lab.yaml"), Replaced(kPlatformLab, "poll_hz: 20", "replay: x.rec"));
  const auto two = RunShell(BinDir() + "/igms-platformd --check-config --config " +
                            dir.File("lab.yaml") + " --name platform 2>&1");
  EXPECT_EQ(two.status, 2) << two.out;
}

TEST(UnknownKeys, RefusedAtStartUnlessAllowed) {
  ScratchDir dir;
  Write(dir.File("lab.yaml"), Replaced(kPlatformLab, "poll_hz: 20", "poll_hx: 20"));
  testing::ChildProcess refused("igms-platformd",
                                {"--config", dir.File("lab.yaml"), "--name", "platform"});
  EXPECT_EQ(refused.Wait(), 2) << refused.Log();
  EXPECT_NE(refused.Log().find("did you mean processes.platform.poll_hz?"), std::string::npos)
      << refused.Log();
  EXPECT_NE(refused.Log().find("--allow-unknown-keys"), std::string::npos) << refused.Log();

  testing::ChildProcess allowed("igms-platformd", {"--config", dir.File("lab.yaml"), "--name",
                                                   "platform", "--allow-unknown-keys"});
  EXPECT_NE(allowed.WaitListening(), 0) << allowed.Log();
  EXPECT_NE(allowed.Log().find("[warning] " + dir.File("lab.yaml") +
                               ":8: unknown key processes.platform.poll_hx"),
            std::string::npos)
      << allowed.Log();
}

TEST(IgmsConfigCheck, TheDeployedLabPassesForEveryProcess) {
  const auto r =
      RunShell(BinDir() + "/igms config check --config " + SourceDir() + "/deploy/lab.yaml 2>&1");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out,
            "lab: OK\ncontrol: OK\nvideo: OK\nobject: OK\nsound: OK\nviewer: OK\njoystick: "
            "OK\nranger: OK\n"
            "voice: OK\nplatform: OK\n");
}

TEST(IgmsConfigCheck, ATypoInOneProcessFailsThatProcess) {
  ScratchDir dir;
  Write(dir.File("lab.yaml"),
        Replaced(DeployLabWithAbsolutePaths(), "    video: video ", "    vidoe: video "));
  const auto r =
      RunShell(BinDir() + "/igms config check --config " + dir.File("lab.yaml") + " 2>&1");
  EXPECT_NE(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("\nobject: FAILED: " + dir.File("lab.yaml") +
                       ":27: unknown key processes.object.vidoe (did you mean "
                       "processes.object.video?)"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("\nvideo: OK\n"), std::string::npos) << r.out;
}

TEST(IgmsConfigCheck, AMissingCalibrationFileFails) {
  ScratchDir dir;
  Write(dir.File("lab.yaml"), Replaced(DeployLabWithAbsolutePaths(), testing::ThesisCalibration(),
                                       dir.File("no-such-calibration.yaml")));
  const auto r =
      RunShell(BinDir() + "/igms config check --config " + dir.File("lab.yaml") + " 2>&1");
  EXPECT_NE(r.status, 0) << r.out;
  EXPECT_EQ(r.out.rfind("lab: FAILED: " + dir.File("lab.yaml") + ":8: lab.calibration names " +
                            dir.File("no-such-calibration.yaml") + ", which does not exist",
                        0),
            0u)
      << r.out;
  EXPECT_NE(r.out.find("\nobject: FAILED: "), std::string::npos) << r.out;
}

TEST(IgmsConfigCheck, AProgramThatIsNotInstalledIsSaidSo) {
  ScratchDir dir;
  Write(dir.File("lab.yaml"),
        std::string(kPlatformLab) + "  telescope:\n    program: igms-telescoped\n    port: 7399\n");
  const auto r =
      RunShell(BinDir() + "/igms config check --config " + dir.File("lab.yaml") + " 2>&1");
  EXPECT_NE(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("\nplatform: OK\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\ntelescope: FAILED: igms-telescoped is not installed"), std::string::npos)
      << r.out;
}

// The lab's log level reaches a process that sets none; its own level wins over it.
TEST(LogLevel, TheLabsLevelAppliesUnderTheProcesssOwn) {
  ScratchDir dir;
  bool expect_debug = true;
  const auto run = [&](const std::string& lab_text) {
    Write(dir.File("lab.yaml"), lab_text);
    testing::ChildProcess daemon("igms-platformd",
                                 {"--config", dir.File("lab.yaml"), "--name", "platform"});
    const uint16_t port = daemon.WaitListening();
    EXPECT_NE(port, 0) << daemon.Log();
    // A client that calls and leaves: the server logs the closed session at debug level.
    {
      testing::TestClient client(port);
      EXPECT_TRUE(client->CallSync<PingResponse>("igms.Server.Ping", PingRequest(), 10s).ok());
    }
    const bool debug = daemon.WaitForLog("] [debug] ", expect_debug ? 20s : 0s);
    EXPECT_EQ(daemon.Terminate(), 0) << daemon.Log();
    return debug || daemon.Log().find("] [debug] ") != std::string::npos;
  };
  expect_debug = true;
  EXPECT_TRUE(run(Replaced(kPlatformLab, "log_level: info", "log_level: debug")));
  expect_debug = false;
  EXPECT_FALSE(
      run(Replaced(kPlatformLab, "log_level: info", "log_level: debug") + "    log_level: info\n"));
}

}  // namespace
}  // namespace igms
