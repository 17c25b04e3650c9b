// WaitFor: a wait on a condition for ASSERT_TRUE / EXPECT_TRUE, whose failure names what
// was awaited and for how long, e.g.
//   ASSERT_TRUE(WaitFor("three readings", [&] { return got.size() >= 3; }));
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <string_view>

#include "tests/support/wait.h"

namespace igms::testing {

template <class Done>
::testing::AssertionResult WaitFor(std::string_view what, Done&& done,
                                   std::chrono::milliseconds limit = std::chrono::seconds(15)) {
  if (WaitUntil(done, limit)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "waited " << limit.count() << " ms for " << what << ", and it did not happen";
}

}  // namespace igms::testing
