// Helpers shared by the device daemon tests: unique pseudo-terminal link paths, an
// io_context on its own thread, waiting for a condition with a deadline, and a thread-safe
// collector of readings.
#pragma once

#include <unistd.h>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <fstream>
#include <thread>
#include <vector>

namespace igms::devices::testing {

inline std::string TempPath(const std::string& name) {
  static int counter = 0;
  return (std::filesystem::temp_directory_path() /
          ("igms-test-" + name + "-" + std::to_string(::getpid()) + "-" +
           std::to_string(++counter)))
      .string();
}

inline void WriteFile(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

// Polls `done` every 2 ms until it holds or `timeout` passes; returns its last value.
inline bool WaitFor(const std::function<bool()>& done,
                    std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return done();
}

class IoThread {
 public:
  IoThread() : guard_(io_.get_executor()), thread_([this] { io_.run(); }) {}
  ~IoThread() { Stop(); }
  void Stop() {
    guard_.reset();
    io_.stop();
    if (thread_.joinable()) thread_.join();
  }
  boost::asio::io_context& io() { return io_; }

 private:
  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> guard_;
  std::thread thread_;
};

// Readings a driver delivered on its io thread, read from the test's thread.
template <class Reading>
struct Collected {
  std::mutex mutex;
  std::vector<Reading> readings;
  void Add(const Reading& r) {
    std::lock_guard lock(mutex);
    readings.push_back(r);
  }
  std::size_t size() {
    std::lock_guard lock(mutex);
    return readings.size();
  }
  Reading last() {
    std::lock_guard lock(mutex);
    return readings.back();
  }
};

}  // namespace igms::devices::testing
