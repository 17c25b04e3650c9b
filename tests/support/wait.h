// Waiting on a condition with a deadline, never on the clock alone: tests and benchmarks poll
// what they wait for, so a loaded machine only makes them slower, not wrong.
#pragma once

#include <chrono>
#include <thread>

namespace igms::testing {

// Polls `done` every `poll` until it holds or `limit` passes; its last answer.
template <class Done>
bool WaitUntil(Done&& done, std::chrono::milliseconds limit = std::chrono::seconds(15),
               std::chrono::milliseconds poll = std::chrono::milliseconds(2)) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < deadline) {
    if (done()) return true;
    std::this_thread::sleep_for(poll);
  }
  return done();
}

}  // namespace igms::testing
