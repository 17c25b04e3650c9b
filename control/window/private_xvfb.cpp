#include "control/window/private_xvfb.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <string>
#include <vector>

namespace igms::control {

Result<std::unique_ptr<PrivateXvfb>> PrivateXvfb::Start(int width, int height) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) return ErrorMessage{"a private Xvfb: no pipe"};
  const std::string screen = std::to_string(width) + "x" + std::to_string(height) + "x24";
  const std::string fd = std::to_string(fds[1]);
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    return ErrorMessage{"a private Xvfb: fork failed"};
  }
  if (pid == 0) {
    // The child: only the write end survives exec (it is how Xvfb names its display).
    fcntl(fds[1], F_SETFD, 0);
    const int null = open("/dev/null", O_RDWR);
    if (null >= 0) {
      dup2(null, STDIN_FILENO);
      dup2(null, STDOUT_FILENO);
      dup2(null, STDERR_FILENO);
    }
    setpgid(0, 0);  // a terminal's Ctrl-C reaches the client, which ends the server
    execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", screen.c_str(), "-nolisten",
           "tcp", "-noreset", static_cast<char*>(nullptr));
    _exit(127);
  }
  close(fds[1]);
  // Xvfb writes its display number and a newline once it accepts connections.
  std::string number;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (number.find('\n') == std::string::npos) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    pollfd p{fds[0], POLLIN, 0};
    if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) break;
    char buffer[16];
    const ssize_t n = read(fds[0], buffer, sizeof buffer);
    if (n <= 0) break;  // it exited (no Xvfb installed: exec failed)
    number.append(buffer, static_cast<size_t>(n));
  }
  close(fds[0]);
  if (number.find('\n') == std::string::npos) {
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    const bool missing = WIFEXITED(status) && WEXITSTATUS(status) == 127;
    return ErrorMessage{missing ? "a private Xvfb: Xvfb is not installed (package xvfb)"
                                : "a private Xvfb did not start within 10 s"};
  }
  number.erase(number.find('\n'));
  const std::string display = ":" + number;
  // Started at start-up, before the client's other threads, which read DISPLAY only later.
  setenv("DISPLAY", display.c_str(), 1);  // NOLINT(concurrency-mt-unsafe): see above
  unsetenv("WAYLAND_DISPLAY");            // NOLINT(concurrency-mt-unsafe): see above
  return std::unique_ptr<PrivateXvfb>(new PrivateXvfb(pid, display));
}

PrivateXvfb::~PrivateXvfb() {
  kill(pid_, SIGTERM);
  int status = 0;
  waitpid(pid_, &status, 0);
}

}  // namespace igms::control
