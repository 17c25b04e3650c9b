// The clocks of every process, in nanoseconds as the wire messages carry them (fields named
// `*_unix_ns` and `*_monotonic_ns`).
#pragma once

#include <chrono>
#include <cstdint>

namespace igms {

// Wall clock since the Unix epoch: stamps that travel between hosts (igms.Header's send time,
// capture and receive times).
inline std::int64_t UnixNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// CLOCK_MONOTONIC (steady_clock on Linux): intervals, and stamps compared between processes
// on one host, which a wall-clock step cannot disturb.
inline std::int64_t MonotonicNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace igms
