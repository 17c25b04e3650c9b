// A private PulseAudio server whose null sink stands in for the sound card: the sink's
// monitor is the capture device OpenAL opens (ALSOFT_DRIVERS=pulse), and Play() speaks a
// sound file into the sink, as a person would speak into a microphone. The environment that
// points every client (the program under test, paplay) at it is set for the test's life.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

#include "tests/support/child_process.h"
#include "tests/support/wait.h"

namespace igms::testing {

class PulseSink {
 public:
  PulseSink() {
    std::filesystem::permissions(scratch_.path(), std::filesystem::perms::owner_all,
                                 std::filesystem::perm_options::replace);
    socket_ = scratch_.File("pulse.socket");
    setenv("PULSE_SERVER", ("unix:" + socket_).c_str(), 1);
    setenv("PULSE_RUNTIME_PATH", scratch_.path().c_str(), 1);
    setenv("XDG_RUNTIME_DIR", scratch_.path().c_str(), 1);
    setenv("ALSOFT_DRIVERS", "pulse", 1);
    server_ = std::make_unique<ChildProcess>(
        "/usr/bin/pulseaudio",
        std::vector<std::string>{
            "-n", "--daemonize=no", "--exit-idle-time=-1", "--disallow-exit", "--log-target=stderr",
            "-L", "module-native-protocol-unix socket=" + socket_ + " auth-anonymous=1", "-L",
            "module-null-sink sink_name=igms_lab rate=16000 channels=1"});
  }
  ~PulseSink() {
    server_.reset();
    for (const char* name :
         {"PULSE_SERVER", "PULSE_RUNTIME_PATH", "XDG_RUNTIME_DIR", "ALSOFT_DRIVERS"})
      unsetenv(name);
  }
  // Whether the pulseaudio and paplay programs are here (deploy/install-deps.sh installs them).
  static bool ToolsPresent() {
    return std::filesystem::exists("/usr/bin/pulseaudio") &&
           std::filesystem::exists("/usr/bin/paplay");
  }
  // Waits up to `timeout` for the server to listen.
  bool WaitReady(std::chrono::seconds timeout = std::chrono::seconds(20)) const {
    return WaitUntil([&] { return std::filesystem::exists(socket_); }, timeout,
                     std::chrono::milliseconds(20));
  }
  // Plays a sound file into the sink; false when paplay fails.
  bool Play(const std::string& wav) const {
    return std::system(("/usr/bin/paplay --device=igms_lab " + wav).c_str()) == 0;
  }
  // Stops the server: the microphone unplugged.
  void Stop() { server_->Terminate(); }
  std::string Log() const { return server_->Log(); }
  std::string File(const std::string& name) const { return scratch_.File(name); }

 private:
  ScratchDir scratch_;
  std::string socket_;
  std::unique_ptr<ChildProcess> server_;
};

}  // namespace igms::testing
