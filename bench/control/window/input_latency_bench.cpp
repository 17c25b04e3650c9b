// The time from a device reading's stamp to the first drawn frame that shows it (issue 20's
// "device reading to frame"): the lab on loopback (every server and daemon, simulated
// devices and site), the control client's session, window drawing and script player in this
// process, drawing offscreen every frame as a window would (software GL, EGL). The script
// freezes, then holds the FlyBox stick deflected: every joystick reading moves the 3D
// pointer. For every frame drawn whose pointer moved and whose newest joystick reading is
// new, the figure is the frame's time once drawn and shown minus that reading's stamp (the
// joystick daemon's CLOCK_MONOTONIC when its serial bytes came: one machine, one clock).
// Readings overtaken before any frame showed them count in no figure.
//
// Usage: bench_input_latency [--seconds S] [--fps F] [--samples N (multisampling, default 4)]
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_main.h"
#include "common/calibration/calibration_file.h"
#include "common/config/process_options.h"
#include "common/stats/percentile.h"
#include "control/app/control_app.h"
#include "control/app/control_config.h"
#include "control/script/script.h"
#include "control/script/script_player.h"
#include "control/window/live_video.h"
#include "control/window/window.h"
#include "control/window/window_loop.h"
#include "tests/support/lab_on_loopback.h"

namespace {

using igms::stats::Percentile;

void Print(const char* what, std::vector<double> ms) {
  if (ms.empty()) {
    std::printf("%-34s no samples\n", what);
    return;
  }
  std::printf("%-34s median %6.1f ms  p95 %6.1f ms  max %6.1f ms  (%zu)\n", what,
              Percentile(ms, 0.5), Percentile(ms, 0.95), *std::max_element(ms.begin(), ms.end()),
              ms.size());
}

int RunBenchmark(int argc, char** argv) {
  setenv("IGMS_BIN_DIR", IGMS_BIN_DIR_DEFAULT, 0);
  setenv("IGMS_SOURCE_DIR", IGMS_SOURCE_DIR_DEFAULT, 0);
  double seconds = 4, fps = 60;
  int samples = 4;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seconds" && i + 1 < argc) {
      seconds = std::atof(argv[++i]);
    } else if (a == "--fps" && i + 1 < argc) {
      fps = std::atof(argv[++i]);
    } else if (a == "--samples" && i + 1 < argc) {
      samples = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: bench_input_latency [--seconds S] [--fps F] [--samples N]\n");
      return 2;
    }
  }
  igms::testing::LabOnLoopback lab;
  if (!lab.Start()) {
    std::fprintf(stderr, "bench_input_latency: %s\n", lab.error().c_str());
    return 1;
  }
  // The control client's options from the lab file, as igms-control reads them.
  std::string file = lab.file();
  std::string program = "bench_input_latency", config_flag = "--config";
  std::vector<char*> args = {program.data(), config_flag.data(), file.data()};
  igms::control::ControlConfig config;
  int exit_code = 0;
  boost::program_options::options_description none;
  auto process = igms::config::ParseProcessOptions(static_cast<int>(args.size()), args.data(),
                                                   "control", "bench", none,
                                                   igms::control::ControlKeys(&config), &exit_code);
  if (!process) return 1;
  const auto calibration = igms::calibration::LoadCalibration(process->lab.calibration);
  auto options = igms::control::MakeControlAppOptions(*process, config);
  if (!calibration.ok() || !options.ok()) {
    std::fprintf(stderr, "bench_input_latency: the lab file: %s\n",
                 options.ok() ? "no calibration" : options.error().c_str());
    return 1;
  }
  igms::control::ScriptPlayerOptions player_options;
  player_options.token = options->token;
  for (const auto& [peer, address] : options->peers) {
    if (igms::control::IsDaemon(peer)) player_options.devices[peer] = address;
  }
  igms::control::LiveVideoOptions live_options;
  live_options.address = options->peers.at(igms::control::Peer::kVideo);
  live_options.token = options->token;
  auto app = igms::control::ControlApp::Make(std::move(*options), *calibration, nullptr);
  if (!app.ok()) {
    std::fprintf(stderr, "bench_input_latency: %s\n", app.error().c_str());
    return 1;
  }
  igms::control::WindowOptions window_options;
  window_options.offscreen = true;
  window_options.samples = samples;
  auto window = igms::control::Window::Open(*calibration, window_options);
  if (!window.ok()) {
    std::fprintf(stderr, "bench_input_latency: %s\n", window.error().c_str());
    return 1;
  }
  auto live = igms::control::LiveVideo::Start(live_options);
  auto script = igms::control::ParseScript(fmt::format("- button: freeze\n"
                                                       "- wait_for: {{mode: model_building}}\n"
                                                       "- stick: {{x: 0.3, y: 0.2, seconds: {}}}\n",
                                                       seconds),
                                           "bench");
  if (!script.ok()) {
    std::fprintf(stderr, "bench_input_latency: %s\n", script.error().c_str());
    return 1;
  }
  (*app)->Start();
  std::atomic<bool> stop = false;
  std::string failure;
  std::thread player_thread([&] {
    const bool started = (*app)->board().WaitFor(
        [](const igms::control::SessionView& v) {
          return v.mode != igms::control::Mode::kStarting || v.exit_code;
        },
        std::chrono::seconds(60));
    if (started && !(*app)->board().Get().exit_code) {
      igms::control::ScriptPlayer player(**app, player_options);
      auto played = player.Play(*script);
      if (!played.ok()) failure = played.error();
    } else {
      failure = "the session did not start";
    }
    stop = true;
  });
  std::vector<double> latency_ms, frame_ms;
  int64_t last_stamp = 0, last_shown = 0, first_shown = 0;
  // The live video as the window's own connection receives it: each new pair's capture to
  // receipt (on this host's clock through the offset from pings) and the pairs' count.
  std::vector<double> live_latency_ms;
  igms::control::LiveStats live_stats;
  std::optional<Eigen::Vector3d> last_pointer;
  igms::control::DisplayLoopOptions loop;
  loop.max_fps = fps;
  loop.offscreen_continuous = true;
  loop.on_frame = [&](const igms::control::SessionView& view, int64_t shown_ns) {
    if (last_shown) frame_ms.push_back(static_cast<double>(shown_ns - last_shown) / 1e6);
    if (!first_shown) first_shown = shown_ns;
    last_shown = shown_ns;
    if (live) {
      const igms::control::LiveStats s = live->stats();
      if (s.frames > live_stats.frames && s.clock_pings > 0)
        live_latency_ms.push_back(s.latency_ms);
      live_stats = s;
    }
    const bool moved = view.pointer && last_pointer && (*view.pointer - *last_pointer).norm() > 0;
    if (moved && view.joystick_stamp_ns > last_stamp && last_stamp != 0) {
      latency_ms.push_back(static_cast<double>(shown_ns - view.joystick_stamp_ns) / 1e6);
    }
    last_stamp = view.joystick_stamp_ns;
    last_pointer = view.pointer;
  };
  igms::control::ScreenshotQueue shots;
  igms::control::RunDisplayLoop(**app, **window, live.get(), shots, stop, loop, true);
  player_thread.join();
  live.reset();
  window->reset();
  app->reset();
  if (!failure.empty()) {
    std::fprintf(stderr, "bench_input_latency: %s\n", failure.c_str());
    return 1;
  }
  std::printf(
      "device reading to frame: the joystick moving the pointer, drawn offscreen "
      "(side by side, %d x %d per eye, %dx multisampling), at most %.0f frames/s\n",
      calibration->left.image_size.width, calibration->left.image_size.height, samples, fps);
  Print("reading stamp to frame shown", latency_ms);
  Print("frame interval", frame_ms);
  const double span_s = static_cast<double>(last_shown - first_shown) / 1e9;
  std::printf(
      "live video into the window: %llu pairs in %.1f s (%.1f per second), %llu skipped; "
      "the video server's clock %+.3f ms (within %.3f ms, %d pings) from this one's\n",
      static_cast<unsigned long long>(live_stats.frames), span_s,
      span_s > 0 ? static_cast<double>(live_stats.frames) / span_s : 0.0,
      static_cast<unsigned long long>(live_stats.skipped), live_stats.clock_offset_ms,
      live_stats.clock_bound_ms, live_stats.clock_pings);
  Print("live pair capture to receipt", live_latency_ms);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return igms::bench::MainReportingFailures(argc, argv, RunBenchmark);
}
