// A daemon as a real child process for tests: started with arguments, its stderr kept in
// a file, its listening port read from its log, stopped with SIGTERM.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "tests/device_daemons/test_util.h"

namespace igms::devices::testing {

inline std::string Bin(const std::string& name) { return std::string(std::getenv("IGMS_BIN_DIR")) + "/" + name; }

class DaemonProcess {
 public:
  DaemonProcess(const std::string& program, std::vector<std::string> args) : log_(TempPath("log")) {
    pid_ = ::fork();
    if (pid_ == 0) {
      const int fd = ::open(log_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(fd, 2);
      std::vector<char*> argv;
      const std::string path = Bin(program);
      argv.push_back(const_cast<char*>(path.c_str()));
      for (auto& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(path.c_str(), argv.data());
      ::_exit(127);
    }
  }
  ~DaemonProcess() {
    if (pid_ > 0 && !exited_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  std::string Log() const {
    std::ifstream in(log_);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  // The port from the "daemon on port N" line; 0 if it did not come within the timeout.
  uint16_t WaitForPort(std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
    uint16_t port = 0;
    WaitFor([&] {
      std::smatch m;
      const std::string log = Log();
      if (std::regex_search(log, m, std::regex("daemon on port ([0-9]+)"))) port = static_cast<uint16_t>(std::stoi(m[1]));
      return port != 0 || Exited();
    }, timeout);
    return port;
  }
  bool Exited() {
    if (exited_) return true;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      exited_ = true;
      exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    return exited_;
  }
  // SIGTERM, then the exit code (-1 if it had to be killed).
  int Stop() {
    if (!exited_) ::kill(pid_, SIGTERM);
    if (!WaitFor([&] { return Exited(); }, std::chrono::seconds(5))) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
      exited_ = true;
      return -1;
    }
    return exit_code_;
  }
  int WaitExit() {
    WaitFor([&] { return Exited(); }, std::chrono::seconds(10));
    return exit_code_;
  }
  pid_t pid() const { return pid_; }

 private:
  std::string log_;
  pid_t pid_ = -1;
  bool exited_ = false;
  int exit_code_ = -1;
};

}  // namespace igms::devices::testing
