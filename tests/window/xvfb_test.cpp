// igms-control --xvfb with no display at all: it starts a virtual X server of its own, opens
// its window there, takes its screenshots, and ends the server with the session.
#include <gtest/gtest.h>
#include <signal.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>

#include "tests/support/child_process.h"
#include "tests/support/lab_on_loopback.h"
#include "tests/support/wait_for.h"

namespace igms::testing {
namespace {

using namespace std::chrono_literals;

TEST(PrivateXvfb, WithoutADisplayTheClientOpensItsWindowOnItsOwnXvfb) {
  unsetenv("DISPLAY");
  unsetenv("WAYLAND_DISPLAY");
  LabOnLoopback lab;
  lab.WriteWithoutStarting();  // no peers: with --wait the session waits, the window draws
  ScratchDir dir;
  ChildProcess control("igms-control",
                       {"--config", lab.file(), "--database", dir.File("igms.db"), "--wait",
                        "--xvfb", "--screenshot-every", "0.2", "--screenshots", dir.File("")});
  ASSERT_TRUE(control.WaitForLog("a private Xvfb on display", 20s)) << control.Log();
  ASSERT_TRUE(control.WaitForLog("window: side-by-side", 20s)) << control.Log();
  const std::string shot = dir.File("igms-every-0001.png");
  ASSERT_TRUE(WaitFor(
      "a screenshot", [&] { return std::filesystem::exists(shot); }, 20s))
      << control.Log();
  std::smatch m;
  const std::string log = control.Log();
  ASSERT_TRUE(std::regex_search(log, m, std::regex(R"(\(pid (\d+)\))"))) << log;
  const pid_t xvfb = std::stoi(m[1]);
  EXPECT_EQ(kill(xvfb, 0), 0) << "the Xvfb is running";
  EXPECT_EQ(control.Terminate(), 0) << control.Log();
  // Its parent reaped it: no such process any more.
  EXPECT_NE(kill(xvfb, 0), 0) << "the private Xvfb outlived the client";
  std::ifstream png(shot, std::ios::binary);
  char magic[4] = {};
  png.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
}

}  // namespace
}  // namespace igms::testing
