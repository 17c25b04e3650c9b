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
    const igms::config::ProcessOptions& process, const igms::control::ControlConfig& config,
    igms::control::ControlAppOptions* options) {
  const auto dir = process.Get<std::string>("export_dir", "");
  if (dir.empty()) return nullptr;
  igms::control::ExportOptions export_options;  // into metres
  const double per_inch = config.session.world_units_per_inch;
  export_options.world_units = {per_inch == 1 ? "in" : "world units", 0.0254 / per_inch};
  auto exports = std::make_unique<igms::control::ExportWriter>(
      process.config.ResolvePath(dir), export_options, [](bool ok, const std::string& what) {
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

}  // namespace

int main(int argc, char** argv) {
  try {
    po::options_description extra("Control client options");
    extra.add_options()("database", po::value<std::string>(),
                        "the geometric database to write or continue (default: lab.database, "
                        "else the operator's data folder)")(
        "wait", po::bool_switch(), "wait for required peers instead of exiting 1")(
        "take-control", po::bool_switch(),
        "take control of the platform from the client holding it (one obeyed at a time)")(
        "script", po::value<std::string>(),
        "play this operator script, then exit (docs/scripts.md)")(
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
    igms::control::ControlConfig control_config;
    int exit_code = 0;
    auto process = igms::config::ParseProcessOptions(
        argc, argv, "control", "igms-control: the operator's modelling session", extra,
        igms::control::ControlKeys(&control_config), &exit_code);
    if (!process) return exit_code;

    const std::string calibration_file = process->config.Get<std::string>("lab.calibration", "");
    if (calibration_file.empty()) {
      spdlog::critical("lab.calibration: the control client needs the cameras' calibration");
      return igms::kExitUsage;
    }
    std::string error;
    const auto calibration =
        igms::calibration::LoadCalibration(process->config.ResolvePath(calibration_file), &error);
    if (!calibration) {
      spdlog::critical("lab.calibration: {}", error);
      return igms::kExitUsage;
    }
    auto options = igms::control::MakeControlAppOptions(*process, control_config);
    if (!options.ok()) {
      spdlog::critical("{}", options.error());
      return igms::kExitUsage;
    }
    options->calibration_hash = igms::calibration::CalibrationHash(*calibration);
    options->session.wait_for_peers = process->flags["wait"].as<bool>();
    options->session.take_control = process->flags["take-control"].as<bool>();
    if (std::string problem; !options->Check(&problem)) {
      spdlog::critical("{}: {}", process->Key(""), problem);
      return igms::kExitUsage;
    }
    const std::string database_flag =
        process->flags.count("database") ? process->flags["database"].as<std::string>() : "";
    auto path = igms::control::ResolveDatabasePath(process->config, database_flag,
                                                   igms::control::UserFolders::FromEnvironment());
    if (!path.ok()) {
      spdlog::critical("the database: {}", path.error());
      return igms::kExitUsage;
    }
    std::optional<igms::control::Script> script;
    if (process->flags.count("script")) {
      auto loaded = igms::control::LoadScript(process->flags["script"].as<std::string>());
      if (!loaded.ok()) {
        spdlog::critical("{}", loaded.error());
        return igms::kExitUsage;
      }
      script = std::move(*loaded);
    }
    const auto stereo = igms::control::render::ParseStereoMode(control_config.stereo);
    if (!stereo) {
      spdlog::critical("{}: stereo '{}' is none of {}", process->Key("stereo"),
                       control_config.stereo, igms::control::render::StereoModeNames());
      return igms::kExitUsage;
    }
    const bool want_window = process->flags["window"].as<bool>();
    const bool no_window = process->flags["no-window"].as<bool>();
    if (want_window && no_window) {
      spdlog::critical("--window and --no-window: choose one");
      return igms::kExitUsage;
    }
    const double screenshot_every = process->flags["screenshot-every"].as<double>();
    if (!(screenshot_every >= 0) || (screenshot_every > 0 && no_window)) {
      spdlog::critical(
          "--screenshot-every {}: a number of seconds (0: none), and not with "
          "--no-window, which draws nothing",
          screenshot_every);
      return igms::kExitUsage;
    }
    const bool want_xvfb = process->flags["xvfb"].as<bool>();
    if (want_xvfb && no_window) {
      spdlog::critical("--xvfb and --no-window: choose one");
      return igms::kExitUsage;
    }
    // A window where there is a display; offscreen (screenshots only) where there is none.
    const bool on_screen =
        want_window || want_xvfb || (!no_window && igms::control::DisplayAvailable());
    bool offscreen = !on_screen && !no_window;
    if (process->check_only) return igms::config::CheckPassed(*process);
    igms::control::ScriptPlayerOptions player_options;
    player_options.token = options->token;
    for (const auto& [peer, address] : options->peers) {
      if (igms::control::IsDaemon(peer)) player_options.devices[peer] = address;
    }

    auto database =
        igms::control::GeometricDatabase::Open(*path, {"igms-control", igms::version::Full()});
    if (!database.ok()) {
      // Another session holds it, or it is not ours: refuse, and leave the file as it was.
      spdlog::critical("the database {}: {}", *path, database.error());
      return igms::kExitFailure;
    }
    spdlog::info("database {}", *path);
    // Declared before the window, so it ends after it.
    std::unique_ptr<igms::control::PrivateXvfb> xvfb;
    if (want_xvfb) {
      if (auto started = StartXvfb(*calibration, &xvfb); !started.ok()) {
        spdlog::critical("--xvfb: {}", started.error());
        return igms::kExitFailure;
      }
    }
    std::unique_ptr<igms::control::Window> window;
    if (on_screen || offscreen) {
      auto opened = OpenWindow(*calibration, *stereo, want_window || want_xvfb, on_screen,
                               &offscreen, &xvfb, process->flags["samples"].as<int>());
      if (!opened.ok()) {
        spdlog::critical("--window: {}", opened.error());
        return igms::kExitFailure;
      }
      window = std::move(*opened);
    }
    std::unique_ptr<igms::control::LiveVideo> live;
    if (window) {
      if (auto it = options->peers.find(igms::control::Peer::kVideo); it != options->peers.end()) {
        igms::control::LiveVideoOptions live_options;
        live_options.address = it->second;
        live_options.token = options->token;
        live_options.client_name = process->name + "-window";
        // Offscreen the video is only looked at for screenshots: a few frames a second do.
        if (offscreen) live_options.fps = 5;
        live = igms::control::LiveVideo::Start(live_options);
      }
    }
    igms::control::ScreenshotQueue shots;
    if (window) {
      // A script's screenshots land beside it (a relative name is the script's folder's).
      const std::filesystem::path folder =
          script ? std::filesystem::path(script->source).parent_path() : std::filesystem::path();
      player_options.screenshot = [&shots, folder](const std::string& file) {
        const std::filesystem::path path(file);
        return shots.Request(path.is_absolute() ? file : (folder / path).string());
      };
    }
    // Destroyed after the app, so the session's last change is written.
    auto exports = StartExports(*process, control_config, &*options);
    auto app =
        igms::control::ControlApp::Make(std::move(*options), *calibration, std::move(*database));
    if (!app.ok()) {
      spdlog::critical("{}", app.error());
      return igms::kExitUsage;
    }

    boost::asio::io_context signals_io;
    boost::asio::signal_set signals(signals_io, SIGINT, SIGTERM);
    signals.async_wait([&](const boost::system::error_code& ec, int signal) {
      if (ec) return;
      spdlog::info("signal {}: ending the session", signal);
      (*app)->Stop(0);
    });
    std::thread signal_thread([&] { signals_io.run(); });
    (*app)->Start();
    // The script plays on its own thread: the display loop keeps the main thread (GLFW's).
    std::thread script_thread;
    if (script) {
      script_thread = std::thread([&] {
        // The script starts once the session has: every required peer answered.
        const bool started = (*app)->board().WaitFor(
            [](const igms::control::SessionView& v) {
              return v.mode != igms::control::Mode::kStarting || v.exit_code;
            },
            std::chrono::hours(24));
        if (!started || (*app)->board().Get().exit_code) return;
        igms::control::ScriptPlayer player(**app, player_options);
        auto played = player.Play(*script);
        if (played.ok()) {
          spdlog::info("script {}: {} actions played", script->source, *played);
          (*app)->Stop(0);
        } else {
          spdlog::error("script {}", played.error());
          (*app)->Stop(1);
        }
      });
    }
    std::atomic<bool> ended = false;
    std::thread display_stopper;
    if (window) {
      // Ends the display loop when the session ends, whoever ends it.
      display_stopper = std::thread([&] {
        (*app)->board().WaitFor(
            [](const igms::control::SessionView& v) { return v.exit_code.has_value(); },
            std::chrono::hours(24 * 365));
        ended = true;
      });
      igms::control::DisplayLoopOptions loop_options;
      loop_options.screenshot_folder = process->flags["screenshots"].as<std::string>();
      loop_options.screenshot_every_s = screenshot_every;
      igms::control::RunDisplayLoop(**app, *window, live.get(), shots, ended, loop_options,
                                    offscreen);
      display_stopper.join();
    }
    if (script_thread.joinable()) script_thread.join();
    const int code = (*app)->Wait();
    signals.cancel();
    signals_io.stop();
    signal_thread.join();
    live.reset();
    window.reset();
    app->reset();  // closes the connections, then the database (recording the session's end)
    return code;
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return igms::kExitUsage;
  }
}
