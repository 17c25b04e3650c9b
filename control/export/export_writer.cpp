#include "control/export/export_writer.h"

#include <utility>

namespace igms::control {

ExportWriter::ExportWriter(std::string folder, ExportOptions options,
                           std::function<void(bool, const std::string&)> report)
    : folder_(std::move(folder)),
      options_(std::move(options)),
      report_(std::move(report)),
      thread_([this] { Run(); }) {}

ExportWriter::~ExportWriter() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void ExportWriter::Update(std::vector<StoredModel> models) {
  {
    std::lock_guard lock(mutex_);
    pending_ = std::move(models);
    ++given_;
  }
  changed_.notify_all();
}

void ExportWriter::Flush() {
  std::unique_lock lock(mutex_);
  const uint64_t target = given_;
  changed_.wait(lock, [&] { return written_ >= target; });
}

void ExportWriter::Run() {
  std::unique_lock lock(mutex_);
  while (true) {
    changed_.wait(lock, [&] { return pending_.has_value() || stopping_; });
    if (!pending_) return;  // stopping, nothing left to write
    std::vector<StoredModel> models = std::move(*pending_);
    pending_.reset();
    const uint64_t covers = given_;
    lock.unlock();
    std::string problem;
    for (const auto& m : models) {
      if (auto why = CheckExportModel(m))
        problem = *why + ": refused, the exports left as they were";
    }
    if (problem.empty()) {
      auto report = WriteAllExports(models, options_, folder_);
      if (report.ok()) {
        report_(true, std::to_string(models.size()) + " models in " +
                          std::to_string(report->written.size()) + " formats to " + folder_);
      } else {
        problem = report.error();
      }
    }
    if (!problem.empty()) report_(false, "exports to " + folder_ + ": " + problem);
    lock.lock();
    written_ = covers;
    changed_.notify_all();
  }
}

}  // namespace igms::control
