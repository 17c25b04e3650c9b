#include "tests/support/child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <regex>
#include <thread>

#include "tests/support/files.h"

namespace igms::testing {

std::string BinDir() {
  const char* dir = std::getenv("IGMS_BIN_DIR");
  return dir != nullptr ? dir : "bin";
}

std::string SourceDir() {
  const char* dir = std::getenv("IGMS_SOURCE_DIR");
  return dir != nullptr ? dir : ".";
}

ShellRun RunShell(const std::string& command) {
  ShellRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  char buffer[4096];
  while (size_t n = fread(buffer, 1, sizeof buffer, pipe)) run.out.append(buffer, n);
  const int status = pclose(pipe);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

std::string ThesisCalibration() {
  return SourceDir() + "/common/calibration/data/thesis_calibration.yaml";
}

ScratchDir::ScratchDir() {
  static std::atomic<int> counter{0};
  path_ = std::filesystem::temp_directory_path() /
          ("igms_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

ScratchDir::~ScratchDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

ChildProcess::ChildProcess(const std::string& program, std::vector<std::string> args) {
  const std::string path =
      program.find('/') == std::string::npos ? BinDir() + "/" + program : program;
  const std::string err = scratch_.File("stderr"), out = scratch_.File("stdout");
  std::vector<std::string> argv = {path};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> raw;
  raw.reserve(argv.size() + 1);
  for (std::string& a : argv) raw.push_back(a.data());
  raw.push_back(nullptr);
  pid_ = ::fork();
  if (pid_ == 0) {
    // Only async-signal-safe calls between fork and exec.
    const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (e < 0 || o < 0) ::_exit(120);
    ::dup2(e, 2);
    ::dup2(o, 1);
    ::execv(raw[0], raw.data());
    ::_exit(127);  // the program is missing: the test sees exit status 127
  }
  if (pid_ < 0) exited_ = true;
}

ChildProcess::~ChildProcess() {
  if (!Exited()) {
    Kill();
    Wait(std::chrono::seconds(5));
  }
}

uint16_t ChildProcess::WaitListening(std::chrono::milliseconds limit) {
  static const std::regex listening("listening on [^ ]+:([0-9]+)");
  const auto end = std::chrono::steady_clock::now() + limit;
  for (;;) {
    std::smatch m;
    const std::string log = Log();
    if (std::regex_search(log, m, listening)) return static_cast<uint16_t>(std::stoi(m[1]));
    if (Exited() || std::chrono::steady_clock::now() > end) return 0;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

bool ChildProcess::WaitForLog(const std::string& text, std::chrono::milliseconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  for (;;) {
    if (Log().find(text) != std::string::npos) return true;
    if (Exited() || std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

std::string ChildProcess::Log() const { return ReadFile(scratch_.File("stderr")); }
std::string ChildProcess::Output() const { return ReadFile(scratch_.File("stdout")); }

bool ChildProcess::Exited() {
  if (exited_) return true;
  int status = 0;
  if (::waitpid(pid_, &status, WNOHANG) == pid_) {
    exited_ = true;
    exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  return exited_;
}

int ChildProcess::Wait(std::chrono::milliseconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (!Exited() && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return exited_ ? exit_status_ : -1;
}

int ChildProcess::Terminate(std::chrono::milliseconds limit) {
  if (Exited()) return exit_status_;
  ::kill(pid_, SIGTERM);
  if (Wait(limit) >= 0) return exit_status_;
  Kill();
  Wait(std::chrono::seconds(5));
  return -1;
}

void ChildProcess::Kill() {
  if (!Exited()) ::kill(pid_, SIGKILL);
}

TestClient::TestClient(uint16_t port, std::string name, std::size_t max_frame_bytes) {
  net::ClientOptions options;
  options.port = port;
  options.name = std::move(name);
  options.max_frame_bytes = max_frame_bytes;
  client_ = std::make_unique<net::Client>(io_.io(), options);
  client_->Start();
}

TestClient::~TestClient() {
  client_->Stop();
  io_.Stop();
}

}  // namespace igms::testing
