// A device daemon as a real child process for tests and benchmarks (ChildProcess runs it,
// keeps its log and reads its port from it), stopped with SIGTERM.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "tests/support/child_process.h"

namespace igms::devices::testing {

class DaemonProcess : public igms::testing::ChildProcess {
 public:
  DaemonProcess(const std::string& program, std::vector<std::string> args)
      : ChildProcess(program, std::move(args)) {}
  // The port it listens on; 0 if it ended or did not listen within the time.
  uint16_t WaitForPort(std::chrono::milliseconds limit = std::chrono::seconds(10)) {
    return WaitListening(limit);
  }
  // SIGTERM, then its exit status (-1 if it had to be killed).
  int Stop() { return Exited() ? exit_status() : Terminate(std::chrono::seconds(5)); }
  // Waits for it to end by itself; its exit status, or -1.
  int WaitExit() { return Wait(std::chrono::seconds(10)); }
};

}  // namespace igms::devices::testing
