#include "common/base/json.h"

#include <gtest/gtest.h>

#include <string>

namespace igms {
namespace {

TEST(JsonEscape, PlainTextPassesUnchanged) {
  EXPECT_EQ(JsonEscape("left camera: 512x480"), "left camera: 512x480");
  EXPECT_EQ(JsonEscape(""), "");
}

TEST(JsonEscape, QuotesAndBackslashesAreEscaped) {
  EXPECT_EQ(JsonEscape(R"(say "box" at C:\lab)"), R"(say \"box\" at C:\\lab)");
}

TEST(JsonEscape, ControlCharactersAreEscaped) {
  EXPECT_EQ(JsonEscape("a\nb\tc"), R"(a\nb\tc)");
  EXPECT_EQ(JsonEscape(std::string("\r\x01\x1f", 3)), R"(\u000d\u0001\u001f)");
  EXPECT_EQ(JsonEscape(std::string("x\0y", 3)), R"(x\u0000y)");
}

TEST(JsonEscape, Utf8PassesUnchanged) {
  EXPECT_EQ(JsonEscape("25 \xc2\xb0 \xe2\x86\x92 pipe"), "25 \xc2\xb0 \xe2\x86\x92 pipe");
  EXPECT_EQ(JsonEscape("\x7f\xff"), "\x7f\xff");
}

TEST(JsonQuote, AddsTheQuotes) {
  EXPECT_EQ(JsonQuote("detail"), "\"detail\"");
  EXPECT_EQ(JsonQuote("a\"b"), R"("a\"b")");
}

}  // namespace
}  // namespace igms
