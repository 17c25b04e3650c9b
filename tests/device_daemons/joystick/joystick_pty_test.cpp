// The joystick driver against the FlyBox simulator on a real pseudo-terminal.
#include <gtest/gtest.h>

#include <mutex>

#include "device_daemons/joystick/flybox_sim.h"
#include "device_daemons/joystick/joystick_driver.h"
#include "device_daemons/serial/pty_host.h"
#include "tests/support/files.h"
#include "tests/support/io_thread.h"
#include "tests/support/readings.h"
#include "tests/support/wait_for.h"

namespace igms::devices {
namespace {

using igms::testing::IoThread;
using igms::testing::TempPath;
using igms::testing::WaitFor;

using Collected = igms::testing::Collected<JoystickState>;

class JoystickPty : public ::testing::Test {
 protected:
  void SetUp() override {
    auto sim = std::make_unique<FlyBoxSim>();
    sim_ = sim.get();
    host_ = std::make_unique<PtyHost>(std::move(sim), PtyHostOptions{TempPath("flybox"), 9600});
    std::string error;
    ASSERT_TRUE(host_->Start(&error)) << error;
  }
  void Set(const JoystickState& s) {
    host_->WithDevice([&](SimulatedDevice&) { sim_->Set(s); });
  }
  std::unique_ptr<JoystickDriver> MakeDriver(IoThread& io, Collected& got, double hz,
                                             bool continuous) {
    JoystickDriverOptions options;
    options.link.port = host_->port();
    options.link.silence_timeout = std::chrono::milliseconds(200);
    options.poll_hz = hz;
    options.continuous = continuous;
    return std::make_unique<JoystickDriver>(io.io(), options,
                                            [&got](const JoystickState& s) { got.Add(s); });
  }
  FlyBoxSim* sim_ = nullptr;
  std::unique_ptr<PtyHost> host_;
};

TEST_F(JoystickPty, PolledReadingsArriveAtTheRateWithTheRightValues) {
  JoystickState s;
  s.set_x(0.75);
  s.set_y(-0.25);
  s.set_twist(0.1);
  s.set_lever1(-1);
  s.set_buttons(0x05);
  s.set_trigger(true);
  Set(s);
  IoThread io;
  Collected got;
  auto driver = MakeDriver(io, got, 25.0, false);
  driver->Start();
  ASSERT_TRUE(WaitFor("the first three readings", [&] { return got.size() >= 3; }));
  // 25 readings, a second of the driver's polling, timed by their own stamps.
  EXPECT_NEAR(got.StampedRate(25), 25.0, 2.5);
  const JoystickState last = got.last();
  EXPECT_NEAR(last.x(), 0.75, 1e-3);
  EXPECT_NEAR(last.y(), -0.25, 1e-3);
  EXPECT_NEAR(last.twist(), 0.1, 1e-3);
  EXPECT_NEAR(last.lever1(), -1.0, 1e-9);
  EXPECT_EQ(last.buttons(), 0x05u);
  EXPECT_TRUE(last.trigger());
  EXPECT_GT(last.stamp().receive_monotonic_ns(), 0);
  EXPECT_EQ(last.stamp().sequence(), got.size());
  // Connected (a loaded machine may have let the 200 ms watchdog fire in between).
  EXPECT_TRUE(WaitFor("the link connected", [&] { return driver->status().state() == CONNECTED; }));

  // The operator moves the stick: the next readings follow.
  s.set_x(-0.5);
  s.set_trigger(false);
  Set(s);
  ASSERT_TRUE(WaitFor(
      "a reading with the stick moved", [&] { return std::abs(got.last().x() + 0.5) < 1e-3; },
      std::chrono::seconds(2)));
  EXPECT_FALSE(got.last().trigger());
  driver->Stop();
  io.Stop();
}

TEST_F(JoystickPty, ContinuousModeStreamsAtTheBoxRate) {
  IoThread io;
  Collected got;
  auto driver = MakeDriver(io, got, 50.0, true);
  driver->Start();
  ASSERT_TRUE(WaitFor("the first three readings", [&] { return got.size() >= 3; }));
  // A second of the box's stream, paced on the readings' own stamps.
  EXPECT_NEAR(got.StampedRate(50), FlyBoxSim::kMaxRateHz, 5.0);
  driver->Stop();
  io.Stop();
}

TEST_F(JoystickPty, GarbageTruncationAndAVanishingPortAreSurvived) {
  JoystickState s;
  s.set_y(0.5);
  Set(s);
  IoThread io;
  Collected got;
  auto driver = MakeDriver(io, got, 50.0, false);
  driver->Start();
  ASSERT_TRUE(WaitFor("the first five readings", [&] { return got.size() >= 5; }));

  host_->InjectGarbage(40);
  host_->TruncateNext();
  ASSERT_TRUE(WaitFor("a bad frame and garbage counted", [&] {
    const LinkStatus st = driver->status();
    return st.bad_frames() >= 1 && st.garbage_bytes() >= 1;
  }));
  size_t before = got.size();
  ASSERT_TRUE(WaitFor("ten more readings", [&] { return got.size() >= before + 10; }));
  EXPECT_NEAR(got.last().y(), 0.5, 1e-3);

  host_->Vanish(std::chrono::milliseconds(400));
  ASSERT_TRUE(WaitFor("the port reopened", [&] { return driver->status().reopens() >= 1; }));
  before = got.size();
  // The driver reopens, identifies and configures the box again, and polling resumes.
  ASSERT_TRUE(WaitFor(
      "ten readings after reopening", [&] { return got.size() >= before + 10; },
      std::chrono::seconds(15)));
  EXPECT_EQ(driver->status().state(), CONNECTED);
  EXPECT_NEAR(got.last().y(), 0.5, 1e-3);
  driver->Stop();
  io.Stop();
}

}  // namespace
}  // namespace igms::devices
