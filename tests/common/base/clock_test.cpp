#include "common/base/clock.h"

#include <gtest/gtest.h>

#include <chrono>
#include <ctime>

namespace igms {
namespace {

// The stamps are the clocks the wire fields name: UnixNs is CLOCK_REALTIME, MonotonicNs
// CLOCK_MONOTONIC (what another process on this host reads), both in nanoseconds.
std::int64_t PosixNs(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return static_cast<std::int64_t>(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

TEST(Clock, UnixNsIsTheWallClockInNanoseconds) {
  const std::int64_t before = PosixNs(CLOCK_REALTIME);
  const std::int64_t stamp = UnixNs();
  const std::int64_t after = PosixNs(CLOCK_REALTIME);
  EXPECT_LE(before, stamp);
  EXPECT_LE(stamp, after);
  // Nanoseconds, not micro- or milliseconds: after 2020-01-01.
  EXPECT_GT(stamp, 1'577'836'800LL * 1'000'000'000);
}

TEST(Clock, MonotonicNsIsClockMonotonicInNanoseconds) {
  const std::int64_t before = PosixNs(CLOCK_MONOTONIC);
  const std::int64_t stamp = MonotonicNs();
  const std::int64_t after = PosixNs(CLOCK_MONOTONIC);
  EXPECT_LE(before, stamp);
  EXPECT_LE(stamp, after);
}

TEST(Clock, MonotonicNsNeverGoesBack) {
  std::int64_t last = MonotonicNs();
  for (int i = 0; i < 10000; ++i) {
    const std::int64_t now = MonotonicNs();
    ASSERT_GE(now, last);
    last = now;
  }
}

}  // namespace
}  // namespace igms
