// igms-control's display loop: on the thread that opened the window, it hands the window's
// keys and mouse to the session as commands, the newest live pair to the window, draws the
// session's view and serves screenshot requests from other threads (the script player).
// Offscreen (no display) it draws only when a screenshot is asked for.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <optional>
#include <string>

#include "common/base/result.h"
#include "control/app/control_app.h"
#include "control/window/live_video.h"
#include "control/window/window.h"

namespace igms::control {

// Screenshot requests: any thread asks, the display loop answers.
class ScreenshotQueue {
 public:
  // Waits until the loop has drawn a frame and written it to `file`, or `timeout`.
  Result<bool> Request(const std::string& file,
                       std::chrono::milliseconds timeout = std::chrono::seconds(10));
  // The loop's side: the oldest request's file, without taking it.
  std::optional<std::string> Next();
  // Answers the oldest request.
  void Done(Result<bool> result);
  // Waits up to `timeout` for a request (the offscreen loop idles here).
  bool WaitForRequest(std::chrono::milliseconds timeout);
  // Refuses pending and later requests (the loop has ended).
  void Close(const std::string& why);

 private:
  struct Pending {
    std::string file;
    std::promise<Result<bool>> done;
  };
  std::mutex mutex_;
  std::condition_variable added_;
  std::deque<Pending> pending_;
  std::optional<std::string> closed_;
};

struct DisplayLoopOptions {
  double max_fps = 60;                  // a window without vsync (Xvfb) draws no faster than this
  std::string screenshot_folder = ".";  // P's screenshots: igms-NNNN.png there
  // --screenshot-every: a screenshot every this many seconds of the session's wall clock
  // (igms-every-NNNN.png in screenshot_folder), whatever the frame rate; 0: none. Seconds,
  // not frames: software GL draws from 6 to under 1 frame a second as the models grow, and
  // an operator's record should keep its pace. Offscreen, the loop draws for them too.
  double screenshot_every_s = 0;
  // Called after each frame is drawn and shown, with the view drawn and when it was shown
  // (ControlApp::NowNs): the benchmarks' probe.
  std::function<void(const SessionView&, int64_t shown_ns)> on_frame;
  // Offscreen, draw every frame (at max_fps) rather than only for screenshots: benchmarks.
  bool offscreen_continuous = false;
};

// Runs until `stop` is set (the session ended). `live` may be null (no video peer).
void RunDisplayLoop(ControlApp& app, Window& window, LiveVideo* live, ScreenshotQueue& shots,
                    const std::atomic<bool>& stop, const DisplayLoopOptions& options,
                    bool offscreen);

}  // namespace igms::control
