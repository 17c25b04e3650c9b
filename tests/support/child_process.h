// What every component's tests need to run the lab's programs for real: a scratch folder, a
// program started as a child process (its stderr kept in a file), the port it listens on,
// and a network client with its own io thread.
//
// Programs are found in IGMS_BIN_DIR (the build tree's bin/, set by igms_test) and data in
// IGMS_SOURCE_DIR (the repository).
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "common/net/client.h"
#include "tests/support/io_thread.h"
#include "tests/support/wait.h"

namespace igms::testing {

// IGMS_BIN_DIR ("bin" when unset) and IGMS_SOURCE_DIR ("." when unset).
std::string BinDir();
std::string SourceDir();
// The thesis's calibration file in the repository.
std::string ThesisCalibration();

// A shell command line run to its end: its exit status (-1 when it could not run or was
// killed) and its stdout. Add " 2>&1" to the line to capture stderr as well, " 2>/dev/null"
// to drop it. The one way tests run a command line.
struct ShellRun {
  int status = -1;
  std::string out;
};
ShellRun RunShell(const std::string& command);

// A folder of its own under the system's temporary folder, removed with everything in it
// when destroyed.
class ScratchDir {
 public:
  ScratchDir();
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  std::string File(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// A program run as a child process. `program` is a name in BinDir() or a path with a '/'.
// Its stderr (where every IGMS program logs) goes to a file that Log() reads; stdout is
// kept too, in a second file. Destroying a process that still runs kills it (SIGKILL).
class ChildProcess {
 public:
  ChildProcess(const std::string& program, std::vector<std::string> args);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // The port from the network library's "listening on HOST:PORT" line, or 0 if the process
  // ended or the time ran out.
  uint16_t WaitListening(std::chrono::milliseconds limit = std::chrono::seconds(30));
  // Waits until `text` appears in the log; false if the process ended or the time ran out.
  bool WaitForLog(const std::string& text,
                  std::chrono::milliseconds limit = std::chrono::seconds(30));

  std::string Log() const;     // stderr so far
  std::string Output() const;  // stdout so far

  // True once the process has ended; exit_status() then holds its exit code, or 128 + the
  // signal that ended it.
  bool Exited();
  // Waits for the end; the exit status, or -1 if it did not end in time.
  int Wait(std::chrono::milliseconds limit = std::chrono::seconds(20));
  // SIGTERM (a graceful stop), then waits; after `limit` it is killed and -1 returned.
  int Terminate(std::chrono::milliseconds limit = std::chrono::seconds(10));
  // SIGKILL, as a crash or a pulled plug would end it.
  void Kill();

  int exit_status() const { return exit_status_; }
  pid_t pid() const { return pid_; }

 private:
  ScratchDir scratch_;
  pid_t pid_ = -1;
  bool exited_ = false;
  int exit_status_ = -1;
};

// A net::Client on loopback with its own io thread, stopped when destroyed.
class TestClient {
 public:
  explicit TestClient(uint16_t port, std::string name = "test",
                      std::size_t max_frame_bytes = 64u << 20);
  ~TestClient();
  TestClient(const TestClient&) = delete;
  TestClient& operator=(const TestClient&) = delete;

  net::Client& operator*() { return *client_; }
  net::Client* operator->() { return client_.get(); }

 private:
  IoThread io_;
  std::unique_ptr<net::Client> client_;
};

}  // namespace igms::testing
