// Runs igms-video-server as a real process on loopback for the tests, and a client for it.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "common/net/client.h"

extern char** environ;

namespace igms::video::testing {

inline std::string BinDir() {
  const char* dir = std::getenv("IGMS_BIN_DIR");
  return dir ? dir : "bin";
}

// A scratch folder removed at the end of the test.
class ScratchDir {
 public:
  ScratchDir() {
    path_ = std::filesystem::temp_directory_path() /
            ("igms_video_" + std::to_string(::getpid()) + "_" + std::to_string(counter_++));
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() { std::filesystem::remove_all(path_); }
  std::string File(const std::string& name) const { return (path_ / name).string(); }

 private:
  static inline int counter_ = 0;
  std::filesystem::path path_;
};

// The server process; stopped with SIGTERM when destroyed.
class ServerProcess {
 public:
  // args: extra command-line arguments (e.g. "--set", "processes.video.backend=files").
  // log_file: when set, the process's stderr (its log) goes there.
  ServerProcess(const ScratchDir& scratch, std::vector<std::string> args,
                const std::string& log_file = "") {
    port_file_ = scratch.File("port-" + std::to_string(++starts_));
    std::filesystem::remove(port_file_);
    std::vector<std::string> argv = {BinDir() + "/igms-video-server", "--name", "video",
                                     "--port-file", port_file_};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<char*> raw;
    for (auto& a : argv) raw.push_back(a.data());
    raw.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    if (!log_file.empty()) {
      posix_spawn_file_actions_addopen(&actions, 2, log_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                       0644);
    }
    if (posix_spawn(&pid_, raw[0], &actions, nullptr, raw.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
  }
  ~ServerProcess() { Stop(); }

  // Waits for the port file; 0 when the process exited or did not listen within 20 s.
  uint16_t WaitPort() {
    for (int i = 0; i < 400 && pid_ > 0; ++i) {
      std::ifstream in(port_file_);
      int port = 0;
      if (in >> port && port > 0) return static_cast<uint16_t>(port);
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
        pid_ = -1;
        return 0;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return 0;
  }

  // Stops the process; returns its exit status.
  int Stop() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      int status = 0;
      waitpid(pid_, &status, 0);
      exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
      pid_ = -1;
    }
    return exit_status_;
  }

  // Waits for the process to exit by itself (bad configuration); its exit status, or -1.
  int WaitExit(std::chrono::seconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (pid_ > 0 && std::chrono::steady_clock::now() < deadline) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
        pid_ = -1;
        return exit_status_;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return pid_ > 0 ? -1 : exit_status_;
  }

  pid_t pid() const { return pid_; }

 private:
  static inline int starts_ = 0;
  pid_t pid_ = -1;
  int exit_status_ = -1;
  std::string port_file_;
};

// A net::Client with its own io thread.
class TestClient {
 public:
  explicit TestClient(uint16_t port, size_t max_frame_bytes = 64u << 20)
      : work_(boost::asio::make_work_guard(io_)) {
    net::ClientOptions options;
    options.port = port;
    options.name = "video-test";
    options.max_frame_bytes = max_frame_bytes;
    client_ = std::make_unique<net::Client>(io_, options);
    thread_ = std::thread([this] { io_.run(); });
    client_->Start();
  }
  ~TestClient() {
    client_->Stop();
    work_.reset();
    io_.stop();
    thread_.join();
  }
  net::Client& operator*() { return *client_; }
  net::Client* operator->() { return client_.get(); }

 private:
  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_;
  std::unique_ptr<net::Client> client_;
  std::thread thread_;
};

}  // namespace igms::video::testing
