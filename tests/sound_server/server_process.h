// A real igms-sound-server process for tests and benchmarks: started with the wave output
// into a scratch file, found through the port it logs, talked to over loopback TCP.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/net/client.h"
#include "igms/sound.pb.h"
#include "sound_server/sound_service.h"

namespace igms::sound::testing {

inline std::filesystem::path ServerBinary() {
  const char* dir = std::getenv("IGMS_BIN_DIR");
  return std::filesystem::path(dir != nullptr ? dir : "bin") / "igms-sound-server";
}

class ServerProcess {
 public:
  // Starts the server with `args` (after the binary), its log going to `log`.
  ServerProcess(const std::vector<std::string>& args, std::filesystem::path log)
      : log_(std::move(log)) {
    std::vector<std::string> argv = {ServerBinary().string(), "--port", "0"};
    argv.insert(argv.end(), args.begin(), args.end());
    pid_ = fork();
    if (pid_ == 0) {
      FILE* out = std::freopen(log_.c_str(), "w", stderr);
      if (out == nullptr) _exit(120);
      std::vector<char*> raw;
      for (std::string& a : argv) raw.push_back(a.data());
      raw.push_back(nullptr);
      execv(raw[0], raw.data());
      _exit(121);
    }
  }
  ~ServerProcess() {
    if (pid_ > 0 && !exited_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }

  std::string Log() const {
    std::ifstream in(log_);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }

  // The port from "listening on HOST:PORT", or 0 if the process exits or the time runs out.
  uint16_t WaitListening(std::chrono::milliseconds limit = std::chrono::seconds(20)) {
    const std::regex listening("listening on [^ ]+:([0-9]+)");
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end) {
      std::smatch m;
      const std::string log = Log();
      if (std::regex_search(log, m, listening)) return static_cast<uint16_t>(std::stoi(m[1]));
      if (Exited()) return 0;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return 0;
  }

  // True once the process has ended (its status is then in exit_status()).
  bool Exited() {
    if (exited_) return true;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      exited_ = true;
      exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    }
    return exited_;
  }
  // Waits for the end; -1 if it did not end in time.
  int Wait(std::chrono::milliseconds limit = std::chrono::seconds(20)) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (!Exited() && std::chrono::steady_clock::now() < end) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return exited_ ? exit_status_ : -1;
  }
  // SIGTERM and wait: the server closes its output, which finishes the wave file.
  int Terminate() {
    if (!Exited()) kill(pid_, SIGTERM);
    return Wait();
  }
  int exit_status() const { return exit_status_; }

 private:
  std::filesystem::path log_;
  pid_t pid_ = -1;
  bool exited_ = false;
  int exit_status_ = -1;
};

// A client of the sound server with its own network thread.
class SoundClient {
 public:
  explicit SoundClient(uint16_t port) : work_(boost::asio::make_work_guard(io_)) {
    net::ClientOptions options;
    options.port = port;
    options.name = "sound-test";
    client_ = std::make_unique<net::Client>(io_, options);
    thread_ = std::thread([this] { io_.run(); });
    client_->Start();
    client_->WaitConnected(std::chrono::seconds(5));
  }
  ~SoundClient() {
    client_->Stop();
    work_.reset();
    io_.stop();
    thread_.join();
  }
  template <class Resp, class Req>
  net::Result<Resp> Call(const std::string& method, const Req& req) {
    return client_->CallSync<Resp>(method, req, std::chrono::seconds(5));
  }
  net::Result<PlayResponse> Play(const std::string& key, Priority priority = PRIORITY_NORMAL,
                                 std::optional<float> volume = std::nullopt) {
    PlayRequest req;
    req.set_key(key);
    req.set_priority(priority);
    if (volume) req.set_volume(*volume);
    return Call<PlayResponse>(kPlayMethod, req);
  }
  net::Result<StatusResponse> Status() {
    return Call<StatusResponse>(kStatusMethod, StatusRequest());
  }
  // Waits until nothing plays or waits; false if that does not happen in time.
  bool WaitIdle(std::chrono::milliseconds limit = std::chrono::seconds(10)) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end) {
      net::Result<StatusResponse> s = Status();
      if (s.ok() && s.value.plays_size() == 0) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }

 private:
  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_;
  std::unique_ptr<net::Client> client_;
  std::thread thread_;
};

}  // namespace igms::sound::testing
