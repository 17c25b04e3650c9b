// The viewer driver against the BOOM simulator on a real pseudo-terminal.
#include <gtest/gtest.h>

#include <mutex>

#include "device_daemons/serial/pty_host.h"
#include "device_daemons/viewer/viewer_driver.h"
#include "device_daemons/viewer/viewer_sim.h"
#include "tests/support/files.h"
#include "tests/support/io_thread.h"
#include "tests/support/readings.h"
#include "tests/support/wait_for.h"

namespace igms::devices {
namespace {

using igms::testing::IoThread;
using igms::testing::TempPath;
using igms::testing::WaitFor;

using Collected = igms::testing::Collected<ViewerState>;

class ViewerPty : public ::testing::Test {
 protected:
  void SetUp() override {
    auto sim = std::make_unique<ViewerSim>();
    sim_ = sim.get();
    host_ = std::make_unique<PtyHost>(std::move(sim), PtyHostOptions{TempPath("boom"), 9600});
    std::string error;
    ASSERT_TRUE(host_->Start(&error)) << error;
  }
  std::unique_ptr<ViewerDriver> MakeDriver(IoThread& io, Collected& got, double hz, bool stream) {
    ViewerDriverOptions options;
    options.link.port = host_->port();
    options.link.silence_timeout = std::chrono::milliseconds(200);
    options.poll_hz = hz;
    options.stream = stream;
    return std::make_unique<ViewerDriver>(io.io(), options,
                                          [&got](const ViewerState& s) { got.Add(s); });
  }
  ViewerSim* sim_ = nullptr;
  std::unique_ptr<PtyHost> host_;
};

TEST_F(ViewerPty, PolledAtTheRequestedRateWithTheSteadyPoseAndButtons) {
  boom::Pose pose;
  pose.x_m = 0.25;
  pose.z_m = -0.1;
  pose.yaw_deg = 30;
  pose.roll_deg = -5;
  host_->WithDevice([&](SimulatedDevice&) {
    sim_->SetSteady(pose);
    sim_->SetButtons(false, true);  // table 2.1: 01
  });
  IoThread io;
  Collected got;
  // 50 Hz leaves the line 30% idle, so the rate holds on a loaded machine; the full 70 Hz
  // is measured by the benchmark.
  auto driver = MakeDriver(io, got, 50.0, false);
  driver->Start();
  ASSERT_TRUE(WaitFor("the first five readings", [&] { return got.size() >= 5; }));
  // A second of polling, timed by the readings' own stamps.
  EXPECT_NEAR(got.StampedRate(50), 50.0, 5.0);
  const ViewerState s = got.last();
  EXPECT_NEAR(s.x_m(), 0.25, boom::kPositionStepM);
  EXPECT_NEAR(s.z_m(), -0.1, boom::kPositionStepM);
  EXPECT_NEAR(s.yaw_deg(), 30, boom::kAngleStepDeg);
  EXPECT_NEAR(s.roll_deg(), -5, boom::kAngleStepDeg);
  EXPECT_FALSE(s.button_left());
  EXPECT_TRUE(s.button_right());
  // Connected (a loaded machine may have let the 200 ms watchdog fire in between).
  EXPECT_TRUE(WaitFor("the link connected", [&] { return driver->status().state() == CONNECTED; }));
  driver->Stop();
  io.Stop();
}

TEST_F(ViewerPty, StreamedPathIsFollowed) {
  auto path = ParseViewerPath("0 0 0 0 0 0 0\n1 0 0 0 90 0 0\n2 0 0 0 0 0 0\n");
  ASSERT_TRUE(path.ok()) << path.error();
  host_->WithDevice([&](SimulatedDevice&) { sim_->SetPath(*path); });
  IoThread io;
  Collected got;
  auto driver = MakeDriver(io, got, 70.0, true);
  driver->Start();
  ASSERT_TRUE(WaitFor("80 streamed readings", [&] { return got.size() >= 80; }));
  std::lock_guard lock(got.mutex);
  double max_yaw = 0;
  for (const auto& r : got.readings) max_yaw = std::max(max_yaw, r.yaw_deg());
  EXPECT_GT(max_yaw, 80.0);  // the head turned towards 90 degrees and back
  // Consecutive device counters advance by one (mod 16): no report was lost.
  for (size_t i = 1; i < got.readings.size(); ++i) {
    EXPECT_EQ((got.readings[i - 1].device_sequence() + 1) % 16, got.readings[i].device_sequence());
  }
  driver->Stop();
  io.Stop();
}

TEST_F(ViewerPty, GarbageTruncationStallAndVanishingAreSurvived) {
  IoThread io;
  Collected got;
  auto driver = MakeDriver(io, got, 70.0, false);
  driver->Start();
  ASSERT_TRUE(WaitFor("the first five readings", [&] { return got.size() >= 5; }));
  host_->InjectGarbage(50);
  host_->TruncateNext();
  ASSERT_TRUE(WaitFor("a bad frame and garbage counted", [&] {
    return driver->status().bad_frames() >= 1 && driver->status().garbage_bytes() >= 1;
  }));
  host_->Stall(std::chrono::milliseconds(300));
  ASSERT_TRUE(WaitFor(
      "the link gone stale", [&] { return driver->status().state() == STALE; },
      std::chrono::seconds(3)));
  size_t before = got.size();
  ASSERT_TRUE(WaitFor("20 readings after the stall", [&] { return got.size() >= before + 20; }));
  host_->Vanish(std::chrono::milliseconds(300));
  ASSERT_TRUE(WaitFor("the port reopened", [&] { return driver->status().reopens() >= 1; }));
  before = got.size();
  ASSERT_TRUE(WaitFor(
      "20 readings after reopening", [&] { return got.size() >= before + 20; },
      std::chrono::seconds(15)));
  EXPECT_EQ(driver->status().state(), CONNECTED);
  driver->Stop();
  io.Stop();
}

}  // namespace
}  // namespace igms::devices
