// Frame ids, unique across restarts of the video server.
//
// A run's ids are consecutive, starting at the wall-clock time the run began in microseconds
// since the Unix epoch. A later run starts from a later time, and no run can issue more ids
// than microseconds pass while it runs (a grab takes far longer than one), so ids never
// repeat across restarts as long as the system clock does not step backwards by more than the
// time between the runs. Consecutive ids within a run let the frame store tell an evicted id
// (issued, then dropped) from one that was never issued.
#pragma once

#include <atomic>
#include <cstdint>

namespace igms::video {

class FrameIdSource {
 public:
  // base: the first id; 0 means "now, in microseconds since the Unix epoch".
  explicit FrameIdSource(uint64_t base = 0);

  // The next id; thread-safe.
  uint64_t Next() { return next_.fetch_add(1); }
  // The first id of this run (every id below it came from an earlier run or nowhere).
  uint64_t first() const { return first_; }

 private:
  uint64_t first_;
  std::atomic<uint64_t> next_;
};

}  // namespace igms::video
