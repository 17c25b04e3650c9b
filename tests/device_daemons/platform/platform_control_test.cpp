// The platform obeys one client connection at a time: a real igms-platformd on its
// simulator, real clients on loopback, and igmsctl as an operator would type it.
#include <gtest/gtest.h>

#include "igms/devices.pb.h"
#include "tests/support/child_process.h"
#include "tests/support/daemon_process.h"
#include "tests/support/wait_for.h"

namespace igms::devices {
namespace {

using igms::testing::RunShell;
using igms::testing::TestClient;
using igms::testing::WaitFor;
using testing::DaemonProcess;
using namespace std::chrono_literals;

const std::string kSet = "igms.devices.PlatformService.SetOrientation";

net::Status Move(net::Client& c, int32_t yaw, bool take = false) {
  SetOrientationRequest r;
  r.set_yaw_ticks(yaw);
  r.set_take_control(take);
  return c.CallSync<SetOrientationResponse>(kSet, r, 3s).status;
}

LinkStatus StatusOf(net::Client& c) {
  return c.CallSync<LinkStatus>("igms.devices.PlatformService.Status", GetStatusRequest(), 2s)
      .value;
}

std::string Controller(net::Client& c) { return StatusOf(c).controller(); }

TEST(PlatformControl, OneClientAtATimeTakeOverAndRelease) {
  DaemonProcess daemon("igms-platformd", {"--simulate", "--port", "0"});
  const uint16_t port = daemon.WaitForPort();
  ASSERT_NE(port, 0) << daemon.Log();
  TestClient first(port, "first_operator");
  auto second = std::make_unique<TestClient>(port, "second_operator");
  ASSERT_TRUE(WaitFor("the platform", [&] { return StatusOf(*first).state() == CONNECTED; }));

  EXPECT_EQ(Controller(*first), "");
  ASSERT_TRUE(Move(*first, 100).ok());
  EXPECT_TRUE(Controller(*first).starts_with("first_operator at 127.0.0.1:")) << Controller(*first);

  // The second is refused, told who holds it, where, and how to take it.
  auto refused = Move(**second, 200);
  EXPECT_EQ(refused.code, igms::PERMISSION_DENIED);
  EXPECT_NE(refused.message.find("controlled by first_operator at 127.0.0.1:"), std::string::npos)
      << refused.message;
  EXPECT_NE(refused.message.find("take_control"), std::string::npos) << refused.message;
  EXPECT_EQ((*second)
                ->CallSync<ResetZeroResponse>("igms.devices.PlatformService.ResetZero",
                                              ResetZeroRequest(), 3s)
                .status.code,
            igms::PERMISSION_DENIED);

  // Taken explicitly: the second commands, the first is told who took it.
  ASSERT_TRUE(Move(**second, 300, true).ok());
  EXPECT_TRUE(Move(**second, 400).ok());
  refused = Move(*first, 500);
  EXPECT_EQ(refused.code, igms::PERMISSION_DENIED);
  EXPECT_NE(refused.message.find("second_operator at 127.0.0.1:"), std::string::npos)
      << refused.message;
  EXPECT_NE(refused.message.find("took control of the platform from this client"),
            std::string::npos)
      << refused.message;
  EXPECT_TRUE(Controller(*first).starts_with("second_operator")) << Controller(*first);

  // The holder's connection closes: control is free, and the first gets it by commanding.
  second.reset();
  ASSERT_TRUE(WaitFor("control released", [&] { return Controller(*first).empty(); }));
  EXPECT_TRUE(Move(*first, 600).ok());
  EXPECT_TRUE(daemon.WaitForLog("second_operator at 127.0.0.1:"));
  EXPECT_EQ(daemon.Stop(), 0);
}

TEST(PlatformControl, IgmsctlIsRefusedThenTakesControl) {
  DaemonProcess daemon("igms-platformd", {"--simulate", "--port", "0"});
  const uint16_t port = daemon.WaitForPort();
  ASSERT_NE(port, 0) << daemon.Log();
  TestClient holder(port, "control");
  ASSERT_TRUE(WaitFor("the platform", [&] { return StatusOf(*holder).state() == CONNECTED; }));
  ASSERT_TRUE(Move(*holder, 100).ok());

  const std::string igmsctl = igms::testing::BinDir() + "/igmsctl --port " + std::to_string(port) +
                              " call PlatformService.SetOrientation '{\"yawTicks\": 50}'";
  const auto refused = RunShell(igmsctl + " 2>&1");
  EXPECT_EQ(refused.status, 1) << refused.out;
  EXPECT_NE(refused.out.find("controlled by control at 127.0.0.1:"), std::string::npos)
      << refused.out;
  const auto taken = RunShell(igmsctl + " --take-control 2>&1");
  EXPECT_EQ(taken.status, 0) << taken.out;
  EXPECT_TRUE(daemon.WaitForLog("took control from control at 127.0.0.1:")) << daemon.Log();
  // igmsctl has exited, so its connection is closed: the platform obeys the first again.
  ASSERT_TRUE(WaitFor("control released", [&] { return Controller(*holder).empty(); }));
  EXPECT_TRUE(Move(*holder, 200).ok());
  const auto wrong = RunShell(igms::testing::BinDir() + "/igmsctl --port " + std::to_string(port) +
                              " call PlatformService.Status --take-control 2>&1");
  EXPECT_EQ(wrong.status, 2) << wrong.out;
  EXPECT_EQ(daemon.Stop(), 0);
}

}  // namespace
}  // namespace igms::devices
