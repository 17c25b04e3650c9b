// A virtual X server of the client's own (Xvfb), for a window where there is no display:
// `igms-control --xvfb`, or by itself where there is no display and EGL offscreen drawing
// is unavailable. It picks a free display number itself (-displayfd), so two clients on one
// machine never collide, and it ends with the object.
#pragma once

#include <sys/types.h>

#include <memory>
#include <string>

#include "common/base/result.h"

namespace igms::control {

class PrivateXvfb {
 public:
  // Starts Xvfb with one screen of `width` x `height` x 24 and sets DISPLAY for this
  // process. An error says why not (no Xvfb installed, or it did not start within 10 s).
  // Call it before other threads start: setting DISPLAY is not safe against their reads.
  static Result<std::unique_ptr<PrivateXvfb>> Start(int width, int height);
  ~PrivateXvfb();  // SIGTERM, then waits for it
  PrivateXvfb(const PrivateXvfb&) = delete;
  PrivateXvfb& operator=(const PrivateXvfb&) = delete;

  const std::string& display() const { return display_; }  // ":N"
  pid_t pid() const { return pid_; }

 private:
  PrivateXvfb(pid_t pid, std::string display) : pid_(pid), display_(std::move(display)) {}
  pid_t pid_;
  std::string display_;
};

}  // namespace igms::control
