// Scratch files for tests: a unique path under the system's temporary folder, and writing
// and reading a whole file.
#pragma once

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace igms::testing {

// A path of its own (not created) under the temporary folder: "igms-test-NAME-PID-N".
inline std::string TempPath(const std::string& name) {
  static std::atomic<int> counter{0};
  return (std::filesystem::temp_directory_path() /
          ("igms-test-" + name + "-" + std::to_string(::getpid()) + "-" +
           std::to_string(++counter)))
      .string();
}

// A folder made afresh (emptied if it was there) under the temporary folder, named after
// `name` and this process.
inline std::filesystem::path FreshTempDir(const std::string& name) {
  std::filesystem::path dir = TempPath(name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline void WriteFile(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

// The whole file; empty when it cannot be read.
inline std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace igms::testing
