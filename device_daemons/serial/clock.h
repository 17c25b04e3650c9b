// Time stamps shared by the daemons, the simulators and the benchmarks: CLOCK_MONOTONIC
// (steady_clock on Linux; comparable between processes on one host) and the wall clock,
// both in nanoseconds.
#pragma once

#include <chrono>
#include <cstdint>

namespace igms::devices {

inline int64_t MonotonicNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

inline int64_t UnixNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Time one character takes on an asynchronous line (start bit, 8 data bits, stop bit).
inline std::chrono::nanoseconds ByteTime(unsigned baud) {
  return std::chrono::nanoseconds(10'000'000'000LL / (baud == 0 ? 1 : baud));
}

}  // namespace igms::devices
