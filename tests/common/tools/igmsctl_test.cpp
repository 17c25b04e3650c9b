// igmsctl and igms as real processes against a real server on loopback.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "common/net/server.h"
#include "tests/support/child_process.h"
#include "tests/support/io_thread.h"

namespace {

using Outcome = igms::testing::ShellRun;
// Runs a command line, capturing stdout (stderr goes to stdout with 2>&1 in the command).
Outcome Shell(const std::string& cmd) { return igms::testing::RunShell(cmd); }

std::string Bin(const std::string& name) {
  return std::string(std::getenv("IGMS_BIN_DIR")) + "/" + name;
}

class IgmsctlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    igms::net::ServerOptions o;
    o.name = "pingable";
    o.token = "tok";
    server_ = std::make_unique<igms::net::Server>(io_.io(), o);
    server_->Start();
  }
  void TearDown() override {
    server_->Stop();
    io_.Stop();
  }
  std::string Port() const { return std::to_string(server_->port()); }

  igms::testing::IoThread io_;
  std::unique_ptr<igms::net::Server> server_;
};

TEST_F(IgmsctlTest, PingPrintsTheServersJson) {
  const Outcome r = Shell(Bin("igmsctl") + " --port " + Port() + " --token tok ping 2>&1");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("\"server_name\":\"pingable\""), std::string::npos) << r.out;
}

TEST_F(IgmsctlTest, CallByUniqueSuffix) {
  const Outcome r =
      Shell(Bin("igmsctl") + " --port " + Port() + " --token tok call Server.Ping '{}' 2>&1");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("\"protocol_version\":1"), std::string::npos) << r.out;
}

TEST_F(IgmsctlTest, WrongTokenIsRefused) {
  const Outcome r = Shell(Bin("igmsctl") + " --port " + Port() + " --token nope ping 2>&1");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.out.find("UNAUTHENTICATED"), std::string::npos) << r.out;
}

TEST_F(IgmsctlTest, BadInputExitsTwoWithAMessage) {
  Outcome r = Shell(Bin("igmsctl") + " --port " + Port() + " call No.Such.Method 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("no method"), std::string::npos) << r.out;
  r = Shell(Bin("igmsctl") + " --port " + Port() +
            " call igms.Server.Ping '{\"nofield\": 1}' 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("not a igms.PingRequest"), std::string::npos) << r.out;
  r = Shell(Bin("igmsctl") + " ping 2>&1");
  EXPECT_EQ(r.status, 2);
}

TEST_F(IgmsctlTest, AbsentServerIsAClearErrorWithoutWaiting) {
  server_->Stop();
  const auto start = std::chrono::steady_clock::now();
  const Outcome r = Shell(Bin("igmsctl") + " --port " + Port() + " --timeout 5000 ping 2>&1");
  EXPECT_EQ(r.status, 2);
  // A refused connection is the answer: igmsctl does not reconnect, so it need not wait.
  EXPECT_NE(r.out.find("not connected to 127.0.0.1:" + Port() + ": Connection refused"),
            std::string::npos)
      << r.out;
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(4));
}

TEST(Igms, DispatchesToSiblingsAndListsThem) {
  Outcome r = Shell(Bin("igms") + " help 2>&1");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("  config\n"), std::string::npos) << r.out;
  r = Shell(Bin("igms") + " no-such-thing 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("no command 'no-such-thing'"), std::string::npos) << r.out;
  const std::string file = ::testing::TempDir() + "/igms_dispatch_lab.yaml";
  FILE* f = fopen(file.c_str(), "w");
  fputs("processes:\n  video:\n    port: 7301\n", f);
  fclose(f);
  r = Shell(Bin("igms") + " config get processes.video.port --config " + file + " 2>&1");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out, "7301\n");
  r = Shell(Bin("igms") + " config get processes.sound.port --config " + file + " 2>&1");
  EXPECT_EQ(r.status, 1) << r.out;
}

}  // namespace
