// From a device reading's stamp to the session state change it causes (issue 17's second
// benchmark): the lab on loopback (every server and daemon, simulated devices and site), the
// control client's I/O and session in this process as igms-control runs them (its options
// from the same lab file), and the operator's hands injected through the simulators'
// SimService.Inject, as the script player does. Each repetition:
//   - freeze: viewer buttons 01 held. The reading that completes the 100 ms hold (table 2.1,
//     measured between stamps as the session does) to the published view whose mode left
//     verification;
//   - pointer: the stick pushed forward. The session moves the pointer by the deflection of
//     one reading held until the next reading's stamp, so the change comes with the second
//     deflected reading: from that reading's stamp to the published view whose pointer moved
//     (and, for the record, from the first deflected reading, one reading period more);
//   - unfreeze: buttons 11 held, the completing reading to the view back in verification.
// Times are the daemon's receive_monotonic_ns (the last byte of the reading off the serial
// line) and this process's CLOCK_MONOTONIC when the view was published. Baseline of the same
// run: the same readings' delivery to a plain Live subscriber in this process (stamp to
// arrival); the difference is what the control client adds (its own delivery, the session,
// the view).
//
// Usage: bench_reading_to_state [--reps N]
#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_main.h"
#include "common/base/clock.h"
#include "common/calibration/calibration_file.h"
#include "common/calibration/calibration_hash.h"
#include "common/config/process_options.h"
#include "common/stats/percentile.h"
#include "control/app/control_app.h"
#include "control/app/control_config.h"
#include "igms/devices.pb.h"
#include "tests/support/child_process.h"
#include "tests/support/lab_on_loopback.h"
#include "tests/support/wait_for.h"

namespace {

using namespace std::chrono_literals;
using igms::MonotonicNs;
using igms::control::Mode;
using igms::control::SessionView;
using igms::stats::Percentile;
using igms::testing::LabOnLoopback;
using igms::testing::TestClient;

constexpr int64_t kHoldNs = 100'000'000;  // the session's button_hold_ns (its default)
// The session's stick_dead_band: the FlyBox's 12-bit centre reads a hair off zero.
constexpr double kDeadBand = 0.05;

// A reading as a plain subscriber saw it: its stamp and when it arrived here.
struct Seen {
  uint64_t sequence = 0;
  int64_t stamp_ns = 0;
  int64_t arrived_ns = 0;
  int buttons = 0;  // viewer: left 2, right 1
  double x = 0;     // joystick: forward deflection
};

// A published view: when, its mode and pointer.
struct Published {
  int64_t at_ns = 0;
  Mode mode = Mode::kStarting;
  std::optional<Eigen::Vector3d> pointer;
};

template <class T>
class Log {
 public:
  void Add(const T& t) {
    std::lock_guard lock(mutex_);
    items_.push_back(t);
  }
  std::vector<T> Since(int64_t ns) const {  // items whose time is after ns
    std::lock_guard lock(mutex_);
    std::vector<T> out;
    for (const T& t : items_)
      if (Time(t) > ns) out.push_back(t);
    return out;
  }

 private:
  static int64_t Time(const Seen& s) { return s.stamp_ns; }
  static int64_t Time(const Published& p) { return p.at_ns; }
  mutable std::mutex mutex_;
  std::vector<T> items_;
};

bool WaitUntil(const std::function<bool()>& done, std::chrono::milliseconds limit = 10s) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(2ms);
  }
  return true;
}

struct Figures {
  std::vector<double> to_state, delivery;
  void Add(int64_t stamp, int64_t state, int64_t arrived) {
    to_state.push_back(static_cast<double>(state - stamp) / 1e6);
    delivery.push_back(static_cast<double>(arrived - stamp) / 1e6);
  }
};

void Print(const char* what, const std::vector<double>& to_state,
           const std::vector<double>& delivery) {
  if (to_state.empty()) {
    std::printf("%-34s (no samples)\n", what);
    return;
  }
  std::printf("%-34s %5zu %9.2f %9.2f %9.2f   %9.2f %9.2f\n", what, to_state.size(),
              Percentile(to_state, 0.5), Percentile(to_state, 0.95), Percentile(to_state, 1),
              Percentile(delivery, 0.5), Percentile(delivery, 0.95));
}

// The reading that completes a hold of `buttons` pressed after `since_ns`: the first reading
// with them whose stamp is kHoldNs or more after the first reading with them.
std::optional<Seen> HoldCompleted(const std::vector<Seen>& readings, int buttons) {
  std::optional<int64_t> from;
  for (const Seen& s : readings) {
    if (s.buttons != buttons) {
      from.reset();
      continue;
    }
    if (!from) from = s.stamp_ns;
    if (s.stamp_ns - *from >= kHoldNs) return s;
  }
  return std::nullopt;
}

// --reps N; nullopt (after the usage) for anything else.
std::optional<int> ParseReps(int argc, char** argv) {
  int reps = 30;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--reps" && i + 1 < argc) {
      reps = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: bench_reading_to_state [--reps N]\n");
      return std::nullopt;
    }
  }
  return reps;
}

// The control client with its options from the lab file, as igms-control reads them; every
// view it publishes goes to `views`. Null (after the reason) when it cannot be made.
std::unique_ptr<igms::control::ControlApp> MakeControlApp(const LabOnLoopback& lab,
                                                          Log<Published>& views) {
  const std::string file = lab.file();
  std::vector<std::string> args = {"bench_reading_to_state", "--config", file, "--log-level",
                                   "warn"};
  std::vector<char*> argv_control;
  argv_control.reserve(args.size());
  for (auto& a : args) argv_control.push_back(a.data());
  igms::control::ControlConfig control_config;
  int exit_code = 0;
  const boost::program_options::options_description no_flags;
  const auto process = igms::config::ParseProcessOptions(
      static_cast<int>(argv_control.size()), argv_control.data(), "control", "bench", no_flags,
      igms::control::ControlKeys(&control_config), &exit_code);
  if (!process) return nullptr;
  const auto calibration = igms::calibration::LoadCalibration(process->lab.calibration);
  if (!calibration.ok()) {
    std::fprintf(stderr, "bench_reading_to_state: lab.calibration: %s\n",
                 calibration.error().c_str());
    return nullptr;
  }
  auto options = igms::control::MakeControlAppOptions(*process, control_config);
  if (!options.ok()) {
    std::fprintf(stderr, "bench_reading_to_state: %s\n", options.error().c_str());
    return nullptr;
  }
  options->calibration_hash = igms::calibration::CalibrationHash(*calibration);
  options->view_published = [&views](const SessionView& v, int64_t now_ns) {
    views.Add({now_ns, v.mode, v.pointer});
  };
  auto made = igms::control::ControlApp::Make(*options, *calibration, nullptr);
  if (!made.ok()) {
    std::fprintf(stderr, "bench_reading_to_state: %s\n", made.error().c_str());
    return nullptr;
  }
  return std::move(*made);
}

// The operator's hands (the simulators' SimService.Inject) and the baseline's plain Live
// subscribers, which log every reading with its stamp and arrival.
class Hands {
 public:
  explicit Hands(const LabOnLoopback& lab)
      : viewer_(lab.port("viewer"), "bench"), joystick_(lab.port("joystick"), "bench") {
    viewer_->Subscribe<igms::devices::ViewerState>(
        "igms.devices.ViewerService.Live", igms::devices::SubscribeRequest(),
        [this](const igms::devices::ViewerState& s) {
          viewer_seen.Add({s.stamp().sequence(), s.stamp().receive_monotonic_ns(), MonotonicNs(),
                           (s.button_left() ? 2 : 0) | (s.button_right() ? 1 : 0), 0});
        });
    joystick_->Subscribe<igms::devices::JoystickState>(
        "igms.devices.JoystickService.Live", igms::devices::SubscribeRequest(),
        [this](const igms::devices::JoystickState& s) {
          joystick_seen.Add(
              {s.stamp().sequence(), s.stamp().receive_monotonic_ns(), MonotonicNs(), 0, s.x()});
        });
  }

  bool Buttons(bool left, bool right) {
    igms::devices::SimInjectRequest r;
    r.mutable_viewer_buttons()->set_button_left(left);
    r.mutable_viewer_buttons()->set_button_right(right);
    return viewer_
        ->CallSync<igms::devices::SimInjectResponse>("igms.devices.SimService.Inject", r, 2s)
        .ok();
  }

  bool Stick(double x) {
    igms::devices::SimInjectRequest r;
    r.mutable_joystick()->set_x(x);
    return joystick_
        ->CallSync<igms::devices::SimInjectResponse>("igms.devices.SimService.Inject", r, 2s)
        .ok();
  }

  Log<Seen> viewer_seen, joystick_seen;

 private:
  TestClient viewer_, joystick_;
};

// One repetition's measurements against the running session.
class Repetition {
 public:
  Repetition(igms::control::ControlApp& app, Hands& hands, const Log<Published>& views)
      : app_(app), hands_(hands), views_(views) {}

  // Freeze: 01 held; the view leaves verification. False when the session did not follow.
  bool Freeze(int rep, Figures& freeze) {
    const int64_t from = MonotonicNs();
    if (!hands_.Buttons(false, true) || !WaitUntil([&] { return ModeIs(Mode::kModelBuilding); }) ||
        !hands_.Buttons(false, false)) {
      return false;
    }
    if (std::getenv("BENCH_DEBUG")) {
      const auto seen = hands_.viewer_seen.Since(from);
      std::fprintf(stderr, "rep %d: %zu viewer readings, %zu views; buttons:", rep, seen.size(),
                   views_.Since(from).size());
      for (const Seen& s : seen) std::fprintf(stderr, " %d", s.buttons);
      std::fprintf(stderr, "\n");
    }
    if (auto hold = HoldCompleted(hands_.viewer_seen.Since(from), 1)) {
      for (const Published& p : views_.Since(from)) {
        if (p.mode == Mode::kVerification) continue;
        freeze.Add(hold->stamp_ns, p.at_ns, hold->arrived_ns);
        break;
      }
    }
    return true;
  }

  // The stick forward: the pointer moves with the second deflected reading. Waits for the
  // stick's zero to reach the session afterwards.
  bool Pointer(Figures& pointer, Figures& pointer_first) {
    const int64_t from = MonotonicNs();
    const auto before = app_.board().Get().pointer;
    if (!hands_.Stick(0.5) || !WaitUntil([&] { return app_.board().Get().pointer != before; }) ||
        !hands_.Stick(0.0)) {
      return false;
    }
    const auto pushed = hands_.joystick_seen.Since(from);
    std::optional<Seen> first, second;
    for (const Seen& s : pushed) {
      if (std::abs(s.x) < kDeadBand) continue;
      if (!first) {
        first = s;
      } else {
        second = s;
        break;
      }
    }
    if (std::getenv("BENCH_DEBUG")) {
      for (const Seen& s : pushed)
        std::fprintf(stderr, "  joy %lu x %.3f stamp %+.2f ms arrived %+.2f\n", s.sequence, s.x,
                     static_cast<double>(s.stamp_ns - from) / 1e6,
                     static_cast<double>(s.arrived_ns - from) / 1e6);
      for (const Published& p : views_.Since(from))
        std::fprintf(stderr, "  view %+.2f ms moved %d\n",
                     static_cast<double>(p.at_ns - from) / 1e6, p.pointer != before);
    }
    if (first && second && second->sequence == first->sequence + 1) {
      for (const Published& p : views_.Since(from)) {
        if (p.pointer == before) continue;
        pointer.Add(second->stamp_ns, p.at_ns, second->arrived_ns);
        pointer_first.Add(first->stamp_ns, p.at_ns, first->arrived_ns);
        break;
      }
    }
    // Let the stick's zero reach the session before unfreezing.
    const int64_t zeroed = MonotonicNs();
    WaitUntil([&] {
      for (const Seen& s : hands_.joystick_seen.Since(zeroed))
        if (std::abs(s.x) < kDeadBand) return true;
      return false;
    });
    return true;
  }

  // Unfreeze: 11 held; back in verification. Waits for the release to reach the session.
  bool Unfreeze(Figures& unfreeze) {
    const int64_t from = MonotonicNs();
    if (!hands_.Buttons(true, true) || !WaitUntil([&] { return ModeIs(Mode::kVerification); }) ||
        !hands_.Buttons(false, false)) {
      return false;
    }
    if (auto hold = HoldCompleted(hands_.viewer_seen.Since(from), 3)) {
      for (const Published& p : views_.Since(from)) {
        if (p.mode != Mode::kVerification) continue;
        unfreeze.Add(hold->stamp_ns, p.at_ns, hold->arrived_ns);
        break;
      }
    }
    // The release reaches the session before the next press.
    const int64_t released = MonotonicNs();
    WaitUntil([&] {
      for (const Seen& s : hands_.viewer_seen.Since(released))
        if (s.buttons == 0) return true;
      return false;
    });
    return true;
  }

  bool ModeIs(Mode m) const { return app_.board().Get().mode == m; }

 private:
  igms::control::ControlApp& app_;
  Hands& hands_;
  const Log<Published>& views_;
};

int RunBenchmark(int argc, char** argv) {
  setenv("IGMS_BIN_DIR", IGMS_BIN_DIR_DEFAULT, 0);
  setenv("IGMS_SOURCE_DIR", IGMS_SOURCE_DIR_DEFAULT, 0);
  const std::optional<int> reps = ParseReps(argc, argv);
  if (!reps) return 2;
  LabOnLoopback lab;
  if (!lab.Start()) {
    std::fprintf(stderr, "bench_reading_to_state: %s\n", lab.error().c_str());
    return 1;
  }
  Log<Published> views;
  const auto made = MakeControlApp(lab, views);
  if (!made) return 1;
  auto& app = *made;
  Hands hands(lab);
  Repetition repetition(app, hands, views);

  app.Start();
  if (!WaitUntil([&] { return repetition.ModeIs(Mode::kVerification); }, 30s)) {
    std::fprintf(stderr, "bench_reading_to_state: the session did not start\n");
    return 1;
  }
  Figures freeze, pointer, pointer_first, unfreeze;
  int failed = 0;
  for (int rep = 0; rep < *reps; ++rep) {
    if (!repetition.Freeze(rep, freeze) || !repetition.Pointer(pointer, pointer_first) ||
        !repetition.Unfreeze(unfreeze)) {
      ++failed;
      break;
    }
  }
  app.Stop();
  app.Wait();

  std::printf("%d repetitions%s; ms from the reading's stamp\n", *reps,
              failed ? " (stopped early: the session did not follow)" : "");
  std::printf("%-34s %5s %9s %9s %9s   %9s %9s\n", "reading -> state change", "n", "median", "p95",
              "max", "Live med", "Live p95");
  Print("viewer 01 held -> freezing", freeze.to_state, freeze.delivery);
  Print("viewer 11 held -> verification", unfreeze.to_state, unfreeze.delivery);
  Print("stick reading -> pointer moved", pointer.to_state, pointer.delivery);
  Print("first deflected -> pointer moved", pointer_first.to_state, pointer_first.delivery);
  std::printf("Live: the same reading's stamp to its arrival at a plain subscriber here.\n");
  return failed ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  return igms::bench::MainReportingFailures(argc, argv, RunBenchmark);
}
