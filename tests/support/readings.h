// Readings a device driver or a daemon's stream delivered on its io thread, read from the
// test's thread; and their rate, measured on the stamps the daemon put in them (the time it
// received each from the device), not on the test's clock, so a test thread that is late to
// look does not change the figure.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

#include "tests/support/wait.h"

namespace igms::testing {

template <class Reading>
struct Collected {
  std::mutex mutex;
  std::vector<Reading> readings;

  void Add(const Reading& r) {
    std::lock_guard lock(mutex);
    readings.push_back(r);
  }
  // A callback that adds to this collection.
  std::function<void(const Reading&)> Sink() {
    return [this](const Reading& r) { Add(r); };
  }
  std::size_t size() {
    std::lock_guard lock(mutex);
    return readings.size();
  }
  Reading last() {
    std::lock_guard lock(mutex);
    return readings.back();
  }

  // Waits for `count` more readings (up to `limit`), then returns their rate per second on
  // their own receive stamps: one over the median interval between consecutive readings.
  // The median is the device's pace; a late wake-up of a loaded machine (a lost period, a
  // late batch) moves only a few intervals. 0 when they did not all arrive in time.
  double StampedRate(std::size_t count,
                     std::chrono::milliseconds limit = std::chrono::seconds(20)) {
    const std::size_t from = size();
    if (from == 0 || count == 0) return 0.0;
    if (!WaitUntil([&] { return size() >= from + count; }, limit)) return 0.0;
    std::vector<int64_t> intervals;
    {
      std::lock_guard lock(mutex);
      for (std::size_t i = from; i < from + count; ++i)
        intervals.push_back(readings[i].stamp().receive_monotonic_ns() -
                            readings[i - 1].stamp().receive_monotonic_ns());
    }
    std::nth_element(intervals.begin(),
                     intervals.begin() + static_cast<std::ptrdiff_t>(intervals.size() / 2),
                     intervals.end());
    const int64_t median_ns = intervals[intervals.size() / 2];
    return median_ns > 0 ? 1e9 / static_cast<double>(median_ns) : 0.0;
  }
};

}  // namespace igms::testing
