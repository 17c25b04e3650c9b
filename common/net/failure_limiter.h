// Failed handshakes and tokens, counted per address (docs/security.md): past
// max_failures within `window`, the address's new connections are closed at once for
// `block`, and the log says so once per burst rather than once per try.
#pragma once

#include <chrono>
#include <map>
#include <mutex>
#include <string>

namespace igms::net {

class FailureLimiter {
 public:
  using Clock = std::chrono::steady_clock;
  struct Options {
    int max_failures = 10;
    std::chrono::milliseconds window{10000};
    std::chrono::milliseconds block{10000};
  };
  explicit FailureLimiter(Options options) : options_(options) {}

  // Records a failure; true when it is the first of a burst (log it), false for the
  // others (counted, and summed up when the address is blocked).
  bool Fail(const std::string& address, Clock::time_point now = Clock::now());
  // True while the address is blocked. *announce is set once per block: log it then, with
  // *failures, the count that caused it.
  bool Blocked(const std::string& address, bool* announce, int* failures,
               Clock::time_point now = Clock::now());

 private:
  struct Entry {
    Clock::time_point window_start;
    int failures = 0;
    Clock::time_point blocked_until;
    bool announced = false;
  };
  Options options_;
  std::mutex mutex_;
  std::map<std::string, Entry> entries_;
};

}  // namespace igms::net
