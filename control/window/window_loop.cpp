#include "control/window/window_loop.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <thread>

namespace igms::control {

Result<bool> ScreenshotQueue::Request(const std::string& file, std::chrono::milliseconds timeout) {
  std::future<Result<bool>> done;
  {
    std::lock_guard lock(mutex_);
    if (closed_) return ErrorMessage{*closed_};
    pending_.push_back(Pending{file, {}});
    done = pending_.back().done.get_future();
  }
  added_.notify_all();
  if (done.wait_for(timeout) != std::future_status::ready) {
    return ErrorMessage{fmt::format("{}: no frame was drawn within {} ms", file, timeout.count())};
  }
  return done.get();
}

std::optional<std::string> ScreenshotQueue::Next() {
  std::lock_guard lock(mutex_);
  if (pending_.empty()) return std::nullopt;
  return pending_.front().file;
}

void ScreenshotQueue::Done(Result<bool> result) {
  std::lock_guard lock(mutex_);
  if (pending_.empty()) return;
  pending_.front().done.set_value(std::move(result));
  pending_.pop_front();
}

bool ScreenshotQueue::WaitForRequest(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  return added_.wait_for(lock, timeout, [&] { return !pending_.empty(); });
}

void ScreenshotQueue::Close(const std::string& why) {
  std::lock_guard lock(mutex_);
  closed_ = why;
  for (auto& p : pending_) p.done.set_value(ErrorMessage{p.file + ": " + why});
  pending_.clear();
}

void RunDisplayLoop(ControlApp& app, Window& window, LiveVideo* live, ScreenshotQueue& shots,
                    const std::atomic<bool>& stop, const DisplayLoopOptions& options,
                    bool offscreen) {
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(1.0 / std::max(1.0, options.max_fps)));
  uint64_t shown = 0;
  int taken = 0;
  auto next = Clock::now();
  uint64_t held_grab = 0;
  auto next_stats = Clock::now() + std::chrono::seconds(5);
  const bool periodic = options.screenshot_every_s > 0;
  const auto every = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(periodic ? options.screenshot_every_s : 1.0));
  auto next_periodic = Clock::now() + every;
  int periodic_taken = 0;
  while (!stop) {
    // Offscreen, the loop follows the video every 100 ms and draws only for a screenshot.
    bool draw = true;
    if (offscreen && !options.offscreen_continuous) {
      std::chrono::milliseconds wait(100);
      if (periodic) {
        wait = std::clamp(
            std::chrono::duration_cast<std::chrono::milliseconds>(next_periodic - Clock::now()),
            std::chrono::milliseconds(0), wait);
      }
      draw = shots.WaitForRequest(wait) || (periodic && Clock::now() >= next_periodic);
    }
    const int64_t now = ControlApp::NowNs();
    const WindowInput input = window.Poll(now);
    for (const Command& c : input.commands) app.Post(c);
    if (input.drive) app.Post(*input.drive);
    if (input.quit) {
      spdlog::info("the window closed: ending the session");
      app.Stop(0);
    }
    const SessionView view = app.board().Get();
    if (live) {
      if (input.offset_move != Eigen::Vector2i::Zero()) {
        live->MoveOffset(input.offset_move.x(), input.offset_move.y());
      }
      if (view.frozen) {
        // Frozen: the grabbed pair, the one the marks and the locate work on.
        const uint64_t id = view.frozen->grab.frame_id();
        if (id != held_grab) {
          if (auto grab = live->Grabbed(id)) {
            window.SetFrame(std::move(*grab));
            held_grab = id;
          } else {
            live->FetchGrab(id);
          }
        }
      } else {
        held_grab = 0;
        if (auto frame = live->Newer(shown)) {
          shown = frame->sequence;
          window.SetFrame(std::move(*frame));
        }
      }
      window.SetVideo(live->lost(), live->overlay());
      // The live video's rate and latency into the window, for the log (docs/window.md).
      if (Clock::now() >= next_stats) {
        next_stats = Clock::now() + std::chrono::seconds(30);
        const LiveStats st = live->stats();
        if (st.frames > 0) {
          spdlog::info(
              "live video: {:.0f} frames/s, capture to receipt {:.1f} ms (the video server's "
              "clock {:+.3f} ms from this one's), {} of {} skipped",
              st.rate_fps, st.latency_ms, st.clock_offset_ms, st.skipped, st.frames + st.skipped);
        }
      }
    } else {
      window.SetVideo(true, {});
    }
    if (!draw) continue;
    std::optional<std::string> path = shots.Next();
    const bool requested = path.has_value();
    if (!path && input.screenshot) {
      path = fmt::format("{}/igms-{:04d}.png", options.screenshot_folder, ++taken);
    }
    if (!path && periodic && Clock::now() >= next_periodic) {
      path = fmt::format("{}/igms-every-{:04d}.png", options.screenshot_folder, ++periodic_taken);
      // A frame slower than the period takes one screenshot, not a burst to catch up.
      next_periodic += every;
      if (next_periodic <= Clock::now()) next_periodic = Clock::now() + every;
    }
    auto drawn = window.Draw(view, path);
    if (options.on_frame) options.on_frame(view, ControlApp::NowNs());
    if (requested) {
      shots.Done(drawn);
    } else if (path) {
      if (drawn.ok()) {
        spdlog::info("screenshot {}", *path);
      } else {
        spdlog::warn("screenshot: {}", drawn.error());
      }
    }
    if (!offscreen || options.offscreen_continuous) {
      next += period;
      const auto now_t = Clock::now();
      if (next > now_t) {
        std::this_thread::sleep_until(next);  // pacing the frames, not waiting on a condition
      } else {
        next = now_t;
      }
    }
  }
  shots.Close("the display has closed");
}

}  // namespace igms::control
