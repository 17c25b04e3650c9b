#include "common/base/environment.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace igms {
namespace {

TEST(EnvironmentVariable, ReturnsTheValueOfASetVariable) {
  ASSERT_EQ(setenv("IGMS_ENVIRONMENT_TEST", "lab a", 1), 0);
  EXPECT_EQ(EnvironmentVariable("IGMS_ENVIRONMENT_TEST"), "lab a");
}

TEST(EnvironmentVariable, TellsAnEmptyValueFromAnUnsetVariable) {
  ASSERT_EQ(setenv("IGMS_ENVIRONMENT_TEST", "", 1), 0);
  EXPECT_EQ(EnvironmentVariable("IGMS_ENVIRONMENT_TEST"), "");
  ASSERT_EQ(unsetenv("IGMS_ENVIRONMENT_TEST"), 0);
  EXPECT_EQ(EnvironmentVariable("IGMS_ENVIRONMENT_TEST"), std::nullopt);
}

}  // namespace
}  // namespace igms
