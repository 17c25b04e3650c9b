#include "video_server/edge_pipeline.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <exception>
#include <stdexcept>

namespace igms::video {
namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// What the two side tasks of one frame share until the second one publishes.
struct PairJob {
  std::weak_ptr<FrameRecord> record;
  std::shared_ptr<EdgePipeline::Counters> counters;
  std::mutex mutex;
  int remaining = 2;
  std::shared_ptr<StereoEdges> edges = std::make_shared<StereoEdges>();
};

void RunSide(const std::shared_ptr<PairJob>& job, bool left, const EdgeOptions& options) {
  std::shared_ptr<FrameRecord> record = job->record.lock();
  EdgeImage result;
  std::string error;
  double ms = 0.0;
  if (record) {
    const auto start = Clock::now();
    try {
      result = DetectEdges(left ? record->images().left : record->images().right, options);
    } catch (const std::exception& e) {
      error = std::string("edge detection failed: ") + e.what();
      spdlog::error("frame {}: {}", record->id(), error);
    }
    ms = MsSince(start);
  }
  std::lock_guard lock(job->mutex);
  StereoEdges& edges = *job->edges;
  (left ? edges.left : edges.right) = std::move(result);
  (left ? edges.left_ms : edges.right_ms) = ms;
  if (!error.empty()) edges.error = error;
  if (--job->remaining > 0) return;
  if (!record) {
    ++job->counters->skipped;
    return;
  }
  ++(edges.error.empty() ? job->counters->done : job->counters->failed);
  edges.ready_ms = MsSince(record->inserted());
  if (!edges.error.empty()) {
    edges.left = EdgeImage{};
    edges.right = EdgeImage{};
  }
  record->SetEdges(job->edges);
}

}  // namespace

EdgePipeline::EdgePipeline(EdgeOptions options, int threads) : options_(options), pool_(threads) {
  if (std::string problem; !options_.Check(&problem)) {
    throw std::invalid_argument(problem);
  }
}

void EdgePipeline::Start(const std::shared_ptr<FrameRecord>& record) {
  auto job = std::make_shared<PairJob>();
  job->record = record;
  job->counters = counters_;
  job->edges->options = options_;
  ++counters_->started;
  pool_.Post([job, this] { RunSide(job, true, options_); });
  pool_.Post([job, this] { RunSide(job, false, options_); });
}

EdgeJobCounts EdgePipeline::Counts() const {
  EdgeJobCounts c;
  // Finished counts first: a job finishing between the loads then shows as in flight,
  // never as a negative number.
  c.done = counters_->done.load();
  c.failed = counters_->failed.load();
  c.skipped = counters_->skipped.load();
  const uint64_t started = counters_->started.load();
  const uint64_t finished = c.done + c.failed + c.skipped;
  c.in_flight = started > finished ? started - finished : 0;
  return c;
}

}  // namespace igms::video
