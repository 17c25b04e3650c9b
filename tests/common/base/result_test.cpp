#include "common/base/result.h"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>

namespace igms {
namespace {

Result<int> ParsePositive(const std::string& text) {
  int value = 0;
  try {
    value = std::stoi(text);
  } catch (const std::exception&) {
    return ErrorMessage{"'" + text + "' is not a number"};
  }
  if (value <= 0) return ErrorMessage{"'" + text + "' must be positive"};
  return value;
}

TEST(Result, HoldsTheValue) {
  const Result<int> r = ParsePositive("42");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value(), 42);
  EXPECT_EQ(*r, 42);
  EXPECT_EQ(r.error(), "");
}

TEST(Result, HoldsTheMessage) {
  const Result<int> r = ParsePositive("-3");
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.error(), "'-3' must be positive");
  EXPECT_EQ(ParsePositive("x").error(), "'x' is not a number");
}

TEST(Result, ValueOfAFailureThrowsWithItsMessage) {
  const Result<int> r = ParsePositive("0");
  try {
    (void)r.value();
    FAIL() << "value() of a failed result returned";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("'0' must be positive"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)*r, std::logic_error);
}

TEST(Result, MovesAValueThatCannotBeCopied) {
  Result<std::unique_ptr<std::string>> r = std::make_unique<std::string>("pipe");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->get()->size(), 4u);
  std::unique_ptr<std::string> taken = std::move(r).value();
  ASSERT_NE(taken, nullptr);
  EXPECT_EQ(*taken, "pipe");
}

TEST(Result, ArrowReachesTheValuesMembers) {
  Result<std::string> r = std::string("cylinder");
  EXPECT_EQ(r->size(), 8u);
  r->append("s");
  EXPECT_EQ(*r, "cylinders");
}

TEST(Result, AStringValueIsNotAnError) {
  const Result<std::string> empty = std::string();
  EXPECT_TRUE(empty.ok());
  const Result<std::string> failed = ErrorMessage{""};
  EXPECT_FALSE(failed.ok());
}

TEST(Fail, StoresTheReasonAndReturnsFalse) {
  std::string why;
  EXPECT_FALSE(Fail(&why, "radius must be > 0"));
  EXPECT_EQ(why, "radius must be > 0");
  EXPECT_FALSE(Fail(nullptr, "nobody asked why"));
}

}  // namespace
}  // namespace igms
