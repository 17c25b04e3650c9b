// Starts edge detection on every grab at once, on a pool of worker threads, so the edges are
// ready while the operator is still marking (the reason the thesis ran edge detection on the
// video server: Cooke, section 2.2.2). The left and right images are two tasks, detected in
// parallel when the pool has two threads.
//
// A frame evicted from the store before its turn is skipped (nobody can ask for it any more),
// so a burst of grabs cannot hold more images alive than the store and the requests in
// flight do.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>

#include "video_server/edges.h"
#include "video_server/frame_store.h"
#include "video_server/worker_pool.h"

namespace igms::video {

// The pipeline's jobs (one per grab, both images) since it started, for GetStatus.
struct EdgeJobCounts {
  uint64_t done = 0;
  uint64_t failed = 0;   // the detector threw on either image
  uint64_t skipped = 0;  // evicted before its turn
  uint64_t in_flight = 0;
};

class EdgePipeline {
 public:
  // options must pass Check() (throws std::invalid_argument otherwise); threads >= 1.
  EdgePipeline(EdgeOptions options, int threads);

  // Queues detection of both images of `record`; the record's SetEdges is called when done.
  void Start(const std::shared_ptr<FrameRecord>& record);

  const EdgeOptions& options() const { return options_; }
  int threads() const { return pool_.size(); }
  EdgeJobCounts Counts() const;

  // Shared with the jobs, which may finish while the pipeline is being destroyed.
  struct Counters {
    std::atomic<uint64_t> started{0}, done{0}, failed{0}, skipped{0};
  };

 private:
  const EdgeOptions options_;
  std::shared_ptr<Counters> counters_ = std::make_shared<Counters>();
  WorkerPool pool_;
};

}  // namespace igms::video
