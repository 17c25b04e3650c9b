// igms-control: the operator's modelling session (Cooke, *Interactive Graphical Model Building
// using Virtual Reality* (1993), section 2.4): the devices, the servers and the geometric
// database, tied together by the session's state machine. docs/control.md.
//
//   igms-control --config lab.yaml [--database FILE] [--wait] [--script FILE]
//                [--window | --no-window] [--stereo MODE] [--screenshots DIR]
//                [--screenshot-every SECONDS] [--xvfb]
//
// The window (docs/window.md) opens when a display is there (or with --window); without one
// the same drawing runs offscreen for the script's screenshots; --no-window draws nothing.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <filesystem>
#include <optional>
#include <thread>
#include <utility>

#include "common/calibration/calibration_file.h"
#include "common/calibration/calibration_hash.h"
#include "common/config/exit_codes.h"
#include "common/config/process_options.h"
#include "common/version/version.h"
#include "control/app/control_app.h"
#include "control/app/control_config.h"
#include "control/database/database_path.h"
#include "control/export/export_writer.h"
#include "control/script/script.h"
#include "control/script/script_player.h"
#include "control/window/live_video.h"
#include "control/window/private_xvfb.h"
#include "control/window/window.h"
#include "control/window/window_loop.h"

namespace po = boost::program_options;

namespace {

// A private Xvfb large enough for the side-by-side window; DISPLAY then names it.
igms::Result<bool> StartXvfb(const igms::calibration::StereoCalibration& calibration,
                             std::unique_ptr<igms::control::PrivateXvfb>* xvfb) {
  const auto size = calibration.left.image_size;
  auto started = igms::control::PrivateXvfb::Start(std::max(1280, 2 * size.width),
                                                   std::max(1024, size.height));
  if (!started.ok()) return igms::ErrorMessage{started.error()};
  *xvfb = std::move(*started);
  spdlog::info("a private Xvfb on display {} (pid {})", (*xvfb)->display(), (*xvfb)->pid());
  return true;
}

// The window, or offscreen drawing for screenshots where no window opens; null (with a
// warning) when neither can be had: the session runs without its picture rather than not at
// all. An error only when --window asked for one. `offscreen` says which it became.
igms::Result<std::unique_ptr<igms::control::Window>> OpenWindow(
    const igms::calibration::StereoCalibration& calibration,
    igms::control::render::StereoMode stereo, bool want_window, bool on_screen, bool* offscreen,
    std::unique_ptr<igms::control::PrivateXvfb>* xvfb, int samples) {
  igms::control::WindowOptions window_options;
  window_options.stereo = stereo;
  window_options.samples = samples;
  window_options.offscreen = *offscreen;
  window_options.help = on_screen;
  auto opened = igms::control::Window::Open(calibration, window_options);
  if (!opened.ok() && want_window) return igms::ErrorMessage{opened.error()};
  if (!opened.ok() && !*offscreen) {
    // A display that will not take a window: draw offscreen for the screenshots.
    spdlog::warn("no window ({}): drawing offscreen", opened.error());
    *offscreen = true;
    window_options.offscreen = true;
    opened = igms::control::Window::Open(calibration, window_options);
  }
  if (!opened.ok() && !igms::control::DisplayAvailable()) {
    // No display and no EGL: a window on a virtual X server of our own, for the screenshots.
    spdlog::warn("no offscreen drawing ({}): starting a private Xvfb", opened.error());
    auto started = StartXvfb(calibration, xvfb);
    if (started.ok()) {
      window_options.offscreen = false;
      window_options.visible = false;
      opened = igms::control::Window::Open(calibration, window_options);
      // Offscreen in spirit: nobody looks at it, it draws for screenshots.
    } else {
      spdlog::warn("{}", started.error());
    }
  }
  if (!opened.ok()) {
    spdlog::warn("no window: {}", opened.error());
    return std::unique_ptr<igms::control::Window>();
  }
  return std::move(*opened);
}

// The exports (processes.control.export_dir): rewritten on their own thread as the models
// change, and once at start. Null when the lab file names no folder.
std::unique_ptr<igms::control::ExportWriter> StartExports(
    const igms::control::ControlConfig& config, igms::control::ControlAppOptions* options) {
  if (config.export_dir.empty()) return nullptr;
  igms::control::ExportOptions export_options;  // into metres
  const double per_inch = config.session.world_units_per_inch;
  export_options.world_units = {per_inch == 1 ? "in" : "world units", 0.0254 / per_inch};
  auto exports = std::make_unique<igms::control::ExportWriter>(
      config.export_dir, export_options, [](bool ok, const std::string& what) {
        if (ok) {
          spdlog::info("exports: {}", what);
        } else {
          spdlog::error("{}", what);
        }
      });
  options->models_changed = [writer =
                                 exports.get()](std::vector<igms::control::StoredModel> models) {
    writer->Update(std::move(models));
  };
  return exports;
}

po::options_description ControlFlags() {
  po::options_description extra("Control client options");
  extra.add_options()("database", po::value<std::string>(),
                      "the geometric database to write or continue (default: lab.database, "
                      "else the operator's data folder)")(
      "wait", po::bool_switch(), "wait for required peers instead of exiting 1")(
      "take-control", po::bool_switch(),
      "take control of the platform from the client holding it (one obeyed at a time)")(
      "script", po::value<std::string>(), "play this operator script, then exit (docs/scripts.md)")(
      "window", po::bool_switch(), "open the window (default: when a display is there)")(
      "no-window", po::bool_switch(), "draw nothing: no window, no offscreen screenshots")(
      "samples", po::value<int>()->default_value(4),
      "multisampling of the graphics' edges (1: none, the cheaper frame in software GL)")(
      "xvfb", po::bool_switch(),
      "open the window on a private virtual X server (Xvfb) started for this session")(
      "screenshots", po::value<std::string>()->default_value("."),
      "the folder of the window's screenshots (key P, --screenshot-every)")(
      "screenshot-every", po::value<double>()->default_value(0),
      "a screenshot every SECONDS (igms-every-NNNN.png in --screenshots), with a window or "
      "offscreen; 0: none");
  return extra;
}

// Everything the session needs that the configuration and flags say, checked before anything
// is opened (--check-config stops after it).
struct Startup {
  igms::calibration::StereoCalibration calibration;
  igms::control::ControlAppOptions options;
  std::string database;
  std::optional<igms::control::Script> script;
  igms::control::render::StereoMode stereo{};
  bool want_window = false;  // --window or --xvfb: a window or nothing
  bool want_xvfb = false;
  bool on_screen = false;  // a window where there is a display
  bool offscreen = false;  // else drawing for screenshots only
  double screenshot_every = 0;
};

igms::Result<Startup> Prepare(const igms::config::ProcessOptions& process,
                              const igms::control::ControlConfig& config) {
  using igms::ErrorMessage;
  Startup s;
  const auto& f = process.flags;
  if (process.lab.calibration.empty()) {
    return ErrorMessage{"lab.calibration: the control client needs the cameras' calibration"};
  }
  auto calibration = igms::calibration::LoadCalibration(process.lab.calibration);
  if (!calibration.ok()) return ErrorMessage{"lab.calibration: " + calibration.error()};
  s.calibration = std::move(*calibration);
  auto options = igms::control::MakeControlAppOptions(process, config);
  if (!options.ok()) return ErrorMessage{options.error()};
  s.options = std::move(*options);
  s.options.calibration_hash = igms::calibration::CalibrationHash(s.calibration);
  s.options.session.wait_for_peers = f["wait"].as<bool>();
  s.options.session.take_control = f["take-control"].as<bool>();
  if (std::string problem; !s.options.Check(&problem)) {
    return ErrorMessage{process.Key("") + ": " + problem};
  }
  const std::string database_flag = f.count("database") ? f["database"].as<std::string>() : "";
  auto path = igms::control::ResolveDatabasePath(process.config, database_flag,
                                                 igms::control::UserFolders::FromEnvironment());
  if (!path.ok()) return ErrorMessage{"the database: " + path.error()};
  s.database = *path;
  if (f.count("script")) {
    auto loaded = igms::control::LoadScript(f["script"].as<std::string>());
    if (!loaded.ok()) return ErrorMessage{loaded.error()};
    s.script = std::move(*loaded);
  }
  const auto stereo = igms::control::render::ParseStereoMode(config.stereo);
  if (!stereo) {
    return ErrorMessage{process.Key("stereo") + ": stereo '" + config.stereo + "' is none of " +
                        igms::control::render::StereoModeNames()};
  }
  s.stereo = *stereo;
  const bool window = f["window"].as<bool>();
  const bool no_window = f["no-window"].as<bool>();
  if (window && no_window) return ErrorMessage{"--window and --no-window: choose one"};
  s.screenshot_every = f["screenshot-every"].as<double>();
  if (!(s.screenshot_every >= 0) || (s.screenshot_every > 0 && no_window)) {
    return ErrorMessage{fmt::format(
        "--screenshot-every {}: a number of seconds (0: none), and not with --no-window, which "
        "draws nothing",
        s.screenshot_every)};
  }
  s.want_xvfb = f["xvfb"].as<bool>();
  if (s.want_xvfb && no_window) return ErrorMessage{"--xvfb and --no-window: choose one"};
  s.want_window = window || s.want_xvfb;
  s.on_screen = s.want_window || (!no_window && igms::control::DisplayAvailable());
  s.offscreen = !s.on_screen && !no_window;
  return s;
}

// What the session draws on: the window (or offscreen drawing), the private Xvfb under it,
// the live video in it.
struct Display {
  // Declared before the window, so it ends after it.
  std::unique_ptr<igms::control::PrivateXvfb> xvfb;
  std::unique_ptr<igms::control::Window> window;
  std::unique_ptr<igms::control::LiveVideo> live;
};

igms::Result<bool> OpenDisplay(const igms::config::ProcessOptions& process, Startup& s,
                               Display* display) {
  if (s.want_xvfb) {
    if (auto started = StartXvfb(s.calibration, &display->xvfb); !started.ok()) {
      return igms::ErrorMessage{"--xvfb: " + started.error()};
    }
  }
  if (!s.on_screen && !s.offscreen) return true;
  auto opened = OpenWindow(s.calibration, s.stereo, s.want_window, s.on_screen, &s.offscreen,
                           &display->xvfb, process.flags["samples"].as<int>());
  if (!opened.ok()) return igms::ErrorMessage{"--window: " + opened.error()};
  display->window = std::move(*opened);
  const auto it = s.options.peers.find(igms::control::Peer::kVideo);
  if (display->window && it != s.options.peers.end()) {
    igms::control::LiveVideoOptions live_options;
    live_options.address = it->second;
    live_options.token = s.options.token;
    live_options.client_name = process.name + "-window";
    // Offscreen the video is only looked at for screenshots: a few frames a second do.
    if (s.offscreen) live_options.fps = 5;
    display->live = igms::control::LiveVideo::Start(live_options);
  }
  return true;
}

// The script's player: the devices to inject into, and screenshots taken by the display loop
// (a relative name is the script's folder's).
igms::control::ScriptPlayerOptions PlayerOptions(const Startup& s, bool window,
                                                 igms::control::ScreenshotQueue* shots) {
  igms::control::ScriptPlayerOptions player;
  player.token = s.options.token;
  for (const auto& [peer, address] : s.options.peers) {
    if (igms::control::IsDaemon(peer)) player.devices[peer] = address;
  }
  if (window) {
    const std::filesystem::path folder =
        s.script ? std::filesystem::path(s.script->source).parent_path() : std::filesystem::path();
    player.screenshot = [shots, folder](const std::string& file) {
      const std::filesystem::path path(file);
      return shots->Request(path.is_absolute() ? file : (folder / path).string());
    };
  }
  return player;
}

// Plays the script on its own thread once the session has started (every required peer
// answered), then ends the session.
std::thread PlayScript(igms::control::ControlApp& app, const igms::control::Script& script,
                       igms::control::ScriptPlayerOptions player_options) {
  return std::thread([&app, &script, player_options = std::move(player_options)] {
    const bool started = app.board().WaitFor(
        [](const igms::control::SessionView& v) {
          return v.mode != igms::control::Mode::kStarting || v.exit_code;
        },
        std::chrono::hours(24));
    if (!started || app.board().Get().exit_code) return;
    igms::control::ScriptPlayer player(app, player_options);
    auto played = player.Play(script);
    if (played.ok()) {
      spdlog::info("script {}: {} actions played", script.source, *played);
      app.Stop(0);
    } else {
      spdlog::error("script {}", played.error());
      app.Stop(1);
    }
  });
}

// Runs the session to its end: signals end it, the script plays on its own thread, and the
// display loop keeps the main thread (GLFW's) until the session ends, whoever ends it.
int RunSession(const igms::config::ProcessOptions& process, igms::control::ControlApp& app,
               const Startup& s, Display& display, igms::control::ScreenshotQueue& shots,
               igms::control::ScriptPlayerOptions player_options) {
  boost::asio::io_context signals_io;
  boost::asio::signal_set signals(signals_io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code& ec, int signal) {
    if (ec) return;
    spdlog::info("signal {}: ending the session", signal);
    app.Stop(0);
  });
  std::thread signal_thread([&] { signals_io.run(); });
  app.Start();
  std::thread script_thread;
  if (s.script) script_thread = PlayScript(app, *s.script, std::move(player_options));
  if (display.window) {
    std::atomic<bool> ended = false;
    std::thread display_stopper([&] {
      app.board().WaitFor(
          [](const igms::control::SessionView& v) { return v.exit_code.has_value(); },
          std::chrono::hours(24 * 365));
      ended = true;
    });
    igms::control::DisplayLoopOptions loop_options;
    loop_options.screenshot_folder = process.flags["screenshots"].as<std::string>();
    loop_options.screenshot_every_s = s.screenshot_every;
    igms::control::RunDisplayLoop(app, *display.window, display.live.get(), shots, ended,
                                  loop_options, s.offscreen);
    display_stopper.join();
  }
  if (script_thread.joinable()) script_thread.join();
  const int code = app.Wait();
  signals.cancel();
  signals_io.stop();
  signal_thread.join();
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    igms::control::ControlConfig control_config;
    int exit_code = 0;
    auto process = igms::config::ParseProcessOptions(
        argc, argv, "control", "igms-control: the operator's modelling session", ControlFlags(),
        igms::control::ControlKeys(&control_config), &exit_code);
    if (!process) return exit_code;
    auto startup = Prepare(*process, control_config);
    if (!startup.ok()) {
      spdlog::critical("{}", startup.error());
      return igms::kExitUsage;
    }
    if (process->check_only) return igms::config::CheckPassed(*process);
    Startup& s = *startup;
    auto database =
        igms::control::GeometricDatabase::Open(s.database, {"igms-control", igms::version::Full()});
    if (!database.ok()) {
      // Another session holds it, or it is not ours: refuse, and leave the file as it was.
      spdlog::critical("the database {}: {}", s.database, database.error());
      return igms::kExitFailure;
    }
    spdlog::info("database {}", s.database);
    Display display;
    if (auto opened = OpenDisplay(*process, s, &display); !opened.ok()) {
      spdlog::critical("{}", opened.error());
      return igms::kExitFailure;
    }
    igms::control::ScreenshotQueue shots;
    auto player_options = PlayerOptions(s, display.window != nullptr, &shots);
    // Destroyed after the app, so the session's last change is written.
    auto exports = StartExports(control_config, &s.options);
    auto app =
        igms::control::ControlApp::Make(std::move(s.options), s.calibration, std::move(*database));
    if (!app.ok()) {
      spdlog::critical("{}", app.error());
      return igms::kExitUsage;
    }
    const int code = RunSession(*process, **app, s, display, shots, std::move(player_options));
    display.live.reset();
    display.window.reset();
    app->reset();  // closes the connections, then the database (recording the session's end)
    return code;
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return igms::kExitUsage;
  }
}
