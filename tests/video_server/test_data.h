// Where the video server's tests find real images: Debian's opencv-doc examples.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace igms::video::testing {

inline std::string OpenCvData(const std::string& name) {
  return "/usr/share/doc/opencv-doc/examples/data/" + name;
}

// Skips the calling test (with the reason) when the opencv-doc images are not installed.
#define IGMS_REQUIRE_OPENCV_DATA()                                                        \
  do {                                                                                    \
    if (!std::filesystem::exists(::igms::video::testing::OpenCvData("left01.jpg"))) {     \
      GTEST_SKIP() << "opencv-doc is not installed (deploy/install-deps.sh installs it)"; \
    }                                                                                     \
  } while (0)

}  // namespace igms::video::testing
