// The whole lab as real processes on loopback, each on a free port: every server and device
// daemon with simulated devices and site, as deploy/lab.yaml runs them, and a lab file
// (file()) naming their ports for the control client, the planner and the truth table. For
// the end-to-end tests of the operator's session. Processes are killed when it is destroyed.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "tests/support/child_process.h"

namespace igms::testing {

class LabOnLoopback {
 public:
  // `control` is processes.control's own lines (indented two more spaces than the entry),
  // `video` the video server's extra lines.
  explicit LabOnLoopback(std::string control = "", std::string video = "");
  // Before Start: process `name`'s own lines instead of deploy/lab.yaml's, and arguments
  // added to its command line (the voice daemon's recogniser: no serial line, --wav FILE).
  void Set(const std::string& name, std::string lines, std::vector<std::string> args = {});
  // False (with the log of the one that failed in error()) when a process did not listen.
  bool Start();
  // Writes the lab file with a port per process where nothing listens (each taken from the
  // system, then let go), and starts nothing: for a control client that finds no one.
  void WriteWithoutStarting();
  const std::string& error() const { return error_; }

  std::string file() const { return dir_.File("lab.yaml"); }
  const ScratchDir& dir() const { return dir_; }
  uint16_t port(const std::string& name) const { return ports_.at(name); }
  ChildProcess& process(const std::string& name) { return *processes_.at(name); }

  // Kills a process (SIGKILL), and starts it again on the same port.
  void Kill(const std::string& name);
  bool Restart(const std::string& name);

 private:
  std::string Text(bool with_ports) const;
  bool Launch(const std::string& name, uint16_t port);

  ScratchDir dir_;
  std::string control_, video_;
  std::map<std::string, std::string> lines_;
  std::map<std::string, std::vector<std::string>> args_;
  std::map<std::string, uint16_t> ports_;
  std::map<std::string, std::unique_ptr<ChildProcess>> processes_;
  std::string error_;
};

}  // namespace igms::testing
