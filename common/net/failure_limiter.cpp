#include "common/net/failure_limiter.h"

namespace igms::net {

bool FailureLimiter::Fail(const std::string& address, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  if (entries_.size() > 4096) {
    // Bounded: forget the quiet ones (a scan of many addresses must not grow this forever).
    for (auto it = entries_.begin(); it != entries_.end();) {
      const bool quiet =
          now - it->second.window_start > options_.window && now >= it->second.blocked_until;
      it = quiet ? entries_.erase(it) : std::next(it);
    }
  }
  Entry& e = entries_[address];
  // A block that has ended leaves the address afresh: its next failure starts a new burst
  // (logged), rather than blocking it again at once.
  const bool block_over = e.failures >= options_.max_failures && now >= e.blocked_until;
  if (e.failures == 0 || now - e.window_start > options_.window || block_over) {
    e.window_start = now;
    e.failures = 0;
  }
  ++e.failures;
  if (e.failures >= options_.max_failures && now >= e.blocked_until) {
    e.blocked_until = now + options_.block;
    e.announced = false;
  }
  return e.failures == 1;
}

bool FailureLimiter::Blocked(const std::string& address, bool* announce, int* failures,
                             Clock::time_point now) {
  std::lock_guard lock(mutex_);
  *announce = false;
  auto it = entries_.find(address);
  if (it == entries_.end() || now >= it->second.blocked_until) return false;
  Entry& e = it->second;
  *failures = e.failures;
  if (!e.announced) {
    e.announced = true;
    *announce = true;
  }
  return true;
}

}  // namespace igms::net
