// igms-video-server as a real process on loopback for tests and benchmarks (ChildProcess
// runs it and reads its port from its log).
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "tests/support/child_process.h"

namespace igms::video::testing {

using igms::testing::BinDir;
using igms::testing::ScratchDir;
using igms::testing::TestClient;

// The server with `args` on a free port (--port 0: its default is the lab's 7301); stopped
// with SIGTERM when destroyed.
class ServerProcess : public igms::testing::ChildProcess {
 public:
  explicit ServerProcess(std::vector<std::string> args)
      : ChildProcess("igms-video-server", WithName(std::move(args))) {}
  ~ServerProcess() { Stop(); }

  // The port it listens on; 0 when it exited or did not listen in time.
  uint16_t WaitPort() {
    if (port_ == 0) port_ = WaitListening();
    return port_;
  }
  // Stops it gracefully; its exit status.
  int Stop() { return Exited() ? exit_status() : Terminate(); }

 private:
  static std::vector<std::string> WithName(std::vector<std::string> args) {
    args.insert(args.begin(), {"--name", "video", "--port", "0"});
    return args;
  }
  uint16_t port_ = 0;
};

}  // namespace igms::video::testing
