// TLS between real processes on loopback (docs/security.md): the lab's authority and
// certificates made by `igms certs lab`, the platform daemon serving with lab.tls: on, and
// igmsctl presenting one certificate or another (--as), or none.
#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <string>

#include "tests/support/daemon_process.h"
#include "tests/support/files.h"

namespace igms::net {
namespace {

using igms::devices::testing::DaemonProcess;
using igms::testing::BinDir;
using igms::testing::RunShell;
using igms::testing::ScratchDir;

TEST(TlsProcesses, OnlyTheControlCertificateMovesThePlatformAndPlainClientsAreTurnedAway) {
  ScratchDir scratch;
  const std::string lab = scratch.File("lab.yaml");
  igms::testing::WriteFile(lab,
                           "lab:\n"
                           "  tls: on\n"
                           "  certs: certs\n"
                           "processes:\n"
                           "  control: {program: igms-control}\n"
                           "  platform: {program: igms-platformd, host: 127.0.0.1, port: 0,"
                           " serial: simulate}\n");
  const std::string bin = BinDir() + "/";
  const auto made = RunShell(bin + "igms-certs lab --config " + lab + " 2>&1");
  ASSERT_EQ(made.status, 0) << made.out;
  const std::string certs = scratch.File("certs");
  EXPECT_EQ(
      std::filesystem::status(certs + "/control.key").permissions() & std::filesystem::perms::all,
      std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
  // A name that is no process of the lab is refused.
  EXPECT_NE(RunShell(bin + "igms-certs issue intruder --config " + lab + " 2>&1").status, 0);

  DaemonProcess platform("igms-platformd", {"--config", lab, "--name", "platform"});
  const uint16_t port = platform.WaitForPort();
  ASSERT_NE(port, 0) << platform.Log();
  EXPECT_NE(platform.Log().find("TLS 1.3"), std::string::npos) << platform.Log();

  const std::string to = bin + "igmsctl --port " + std::to_string(port) + " --timeout 3000 ";
  const std::string move = " call PlatformService.SetOrientation '{}' 2>&1";
  // The diagnostic certificate reads, and may not move the platform.
  const auto ping = RunShell(to + "--certs " + certs + " ping 2>&1");
  EXPECT_EQ(ping.status, 0) << ping.out;
  const auto refused = RunShell(to + "--certs " + certs + " --as igmsctl" + move);
  EXPECT_NE(refused.status, 0);
  EXPECT_NE(refused.out.find("PERMISSION_DENIED"), std::string::npos) << refused.out;
  EXPECT_TRUE(platform.WaitForLog("refused igms.devices.PlatformService.SetOrientation"))
      << platform.Log();
  // A plain client is told the server wants TLS.
  const auto plain = RunShell(to + "ping 2>&1");
  EXPECT_NE(plain.status, 0);
  EXPECT_NE(plain.out.find("requires TLS"), std::string::npos) << plain.out;
  // The control certificate moves it; the daemon served every one of them.
  const auto moved = RunShell(to + "--certs " + certs + " --as control" + move);
  EXPECT_EQ(moved.status, 0) << moved.out;
  // SIGHUP: the certificates are read again, the daemon goes on.
  ::kill(platform.pid(), SIGHUP);
  EXPECT_TRUE(platform.WaitForLog("certificate files read again")) << platform.Log();
  EXPECT_EQ(RunShell(to + "--certs " + certs + " ping 2>&1").status, 0);
  EXPECT_EQ(platform.Stop(), 0) << platform.Log();
}

}  // namespace
}  // namespace igms::net
