#include "common/base/errno_text.h"

#include <gtest/gtest.h>

#include <cerrno>

namespace igms {
namespace {

TEST(ErrnoText, SaysWhatStrerrorSays) {
  EXPECT_EQ(ErrnoText(ENOENT), "No such file or directory");
  EXPECT_EQ(ErrnoText(EACCES), "Permission denied");
}

TEST(ErrnoText, NamesAnUnknownNumber) { EXPECT_EQ(ErrnoText(99999), "Unknown error 99999"); }

}  // namespace
}  // namespace igms
