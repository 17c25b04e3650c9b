// The control client's network loop ends by itself when the client is destroyed, however
// busy it was: its own timers (the session's tick, the peers' health) must not re-arm once
// the loop is told to end, or ~ControlApp waits out its grace period (a warning and 3 s at
// every exit of igms-control with a window, as seen before this test).
#include <gtest/gtest.h>

#include <chrono>

#include "common/calibration/calibration_file.h"
#include "control/app/control_app.h"
#include "tests/support/child_process.h"

namespace igms::control {
namespace {

using namespace std::chrono_literals;

TEST(ControlAppExit, TheLoopEndsByItselfEvenWhenATimerFiresDuringShutdown) {
  const auto calibration = calibration::LoadCalibration(testing::ThesisCalibration());
  ASSERT_TRUE(calibration.ok()) << calibration.error();
  for (int run = 0; run < 150; ++run) {
    SCOPED_TRACE("run " + std::to_string(run));
    ControlAppOptions options;
    options.session.wait_for_peers = true;  // no peers: the session waits, ticking
    // Timers due every millisecond, and a queue of commands ahead of the shutdown: the loop
    // is busy when the shutdown comes and both timers have expired behind it, the case
    // that used to re-arm them for ever.
    options.tick = 1ms;
    options.health_period = 1ms;
    auto app = ControlApp::Make(options, *calibration, nullptr);
    ASSERT_TRUE(app.ok()) << app.error();
    (*app)->Start();
    for (int i = 0; i < 2000; ++i) (*app)->Post(PointerDrive{0.1, 0, 0, ControlApp::NowNs()});
    const auto start = std::chrono::steady_clock::now();
    app->reset();
    const auto took = std::chrono::steady_clock::now() - start;
    // The grace period is 3 s; a loop that ends by itself takes milliseconds.
    ASSERT_LT(took, 1s) << "the network loop did not end by itself";
  }
}

}  // namespace
}  // namespace igms::control
