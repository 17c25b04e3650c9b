// A real server process reports its program and version in igms.Server.Ping, as its
// --version prints them and `igmsctl ping` shows them.
#include <gtest/gtest.h>

#include <string>

#include "common/version/version.h"
#include "tests/support/child_process.h"

namespace igms::version {
namespace {

using igms::testing::BinDir;
using igms::testing::ChildProcess;
using igms::testing::RunShell;

TEST(Ping, CarriesTheServersProgramAndVersion) {
  ChildProcess daemon("igms-joystickd", {"--simulate", "--port", "0"});
  const uint16_t port = daemon.WaitListening();
  ASSERT_NE(port, 0) << daemon.Log();
  const auto ping =
      RunShell("'" + BinDir() + "/igmsctl' --port " + std::to_string(port) + " ping 2>&1");
  ASSERT_EQ(ping.status, 0) << ping.out;
  EXPECT_NE(ping.out.find("\"program\":\"igms-joystickd\""), std::string::npos) << ping.out;
  EXPECT_NE(ping.out.find("\"version\":\"" + Full() + "\""), std::string::npos) << ping.out;
  const auto printed = RunShell("'" + BinDir() + "/igms-joystickd' --version");
  EXPECT_EQ(printed.out, "igms-joystickd " + Full() + "\n");
  EXPECT_EQ(daemon.Terminate(), 0) << daemon.Log();
}

}  // namespace
}  // namespace igms::version
