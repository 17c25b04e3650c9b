// The control client's exports: every format rewritten into one folder whenever the session's
// models change, so a robot's planner that reloads a file stays current while the operator
// works (docs/exports.md). Writing runs on a thread of its own, never on the session's: the
// newest list of models wins, and a burst of changes is written once.
#pragma once

#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "control/export/export.h"

namespace igms::control {

class ExportWriter {
 public:
  // `report` hears each export's outcome ("7 models in 7 formats to DIR", or the error).
  ExportWriter(std::string folder, ExportOptions options,
               std::function<void(bool ok, const std::string& what)> report);
  // Writes what is pending, then stops.
  ~ExportWriter();
  ExportWriter(const ExportWriter&) = delete;
  ExportWriter& operator=(const ExportWriter&) = delete;

  // The models present now; returns at once.
  void Update(std::vector<StoredModel> models);
  // Blocks until every update given so far is written (tests, and the end of a session).
  void Flush();

 private:
  void Run();

  const std::string folder_;
  const ExportOptions options_;
  const std::function<void(bool, const std::string&)> report_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::optional<std::vector<StoredModel>> pending_;
  uint64_t given_ = 0, written_ = 0;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace igms::control
