#pragma once

#include <chrono>
#include <cstdint>

namespace igms::net {

// Wall clock in nanoseconds since the Unix epoch, as carried in igms.Header.
inline std::int64_t UnixNanos() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Monotonic clock in nanoseconds, for measuring intervals within one process.
inline std::int64_t MonotonicNanos() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace igms::net
