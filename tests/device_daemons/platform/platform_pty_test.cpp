// The platform driver against the MOLLY simulator on a real pseudo-terminal.
#include <gtest/gtest.h>

#include <cmath>
#include <future>
#include <mutex>

#include "device_daemons/platform/molly_sim.h"
#include "device_daemons/platform/platform_driver.h"
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

using Collected = igms::testing::Collected<PlatformState>;

std::pair<bool, std::string> Wait(std::future<std::pair<bool, std::string>>& f) {
  if (f.wait_for(std::chrono::seconds(5)) != std::future_status::ready) return {false, "no answer"};
  return f.get();
}

class PlatformPty : public ::testing::Test {
 protected:
  void SetUp() override {
    MollySimOptions options;
    options.backlash_deg = 1.59;
    auto sim = std::make_unique<MollySim>(options);
    sim_ = sim.get();
    host_ = std::make_unique<PtyHost>(std::move(sim), PtyHostOptions{TempPath("molly"), 9600});
    std::string error;
    ASSERT_TRUE(host_->Start(&error)) << error;
    PlatformDriverOptions driver_options;
    driver_options.link.port = host_->port();
    driver_options.link.silence_timeout = std::chrono::milliseconds(200);
    driver_ = std::make_unique<PlatformDriver>(io_.io(), driver_options,
                                               [this](const PlatformState& s) { got_.Add(s); });
    driver_->Start();
    ASSERT_TRUE(WaitFor("the first three readings", [&] { return got_.size() >= 3; }));
  }
  void TearDown() override {
    if (driver_) driver_->Stop();
    io_.Stop();
  }
  std::pair<bool, std::string> Set(molly::Ticks t, uint32_t steps) {
    std::promise<std::pair<bool, std::string>> p;
    auto f = p.get_future();
    driver_->SetOrientation(t, steps, [&p](bool ok, const std::string& m) {
      p.set_value({ok, m});
    });
    return Wait(f);
  }
  MollySim* sim_ = nullptr;
  std::unique_ptr<PtyHost> host_;
  IoThread io_;
  Collected got_;
  std::unique_ptr<PlatformDriver> driver_;
};

TEST_F(PlatformPty, SetOrientationIsReachedAndPublishedInTicksAndDegrees) {
  const molly::Ticks target{static_cast<int32_t>(std::lround(30.0 / molly::kYawDegPerTick)),
                            static_cast<int32_t>(std::lround(10.0 / molly::kPitchRollDegPerTick)),
                            -57};
  auto [ok, message] = Set(target, 50);
  ASSERT_TRUE(ok) << message;
  // Published while moving, then settled exactly on the target ticks.
  ASSERT_TRUE(WaitFor(
      "the platform moving", [&] { return got_.last().moving(); }, std::chrono::seconds(2)));
  ASSERT_TRUE(WaitFor(
      "the platform at rest at the target",
      [&] {
        const auto s = got_.last();
        return !s.moving() && s.yaw_ticks() == target.yaw;
      },
      std::chrono::seconds(5)));
  const PlatformState s = got_.last();
  EXPECT_EQ(s.pitch_ticks(), target.pitch);
  EXPECT_EQ(s.roll_ticks(), target.roll);
  EXPECT_NEAR(s.yaw_deg(), 30.0, molly::kYawDegPerTick);
  EXPECT_NEAR(s.pitch_deg(), 10.0, molly::kPitchRollDegPerTick);
  EXPECT_NEAR(s.roll_deg(), -57 * molly::kPitchRollDegPerTick, 1e-12);
  EXPECT_EQ(driver_->status().state(), CONNECTED);
}

TEST_F(PlatformPty, ResetZeroAndBacklashAsTheThesisMeasured) {
  ASSERT_TRUE(
      Set({0, static_cast<int32_t>(std::lround(20.0 / molly::kPitchRollDegPerTick)), 0}, 1).first);
  ASSERT_TRUE(WaitFor("the platform at rest pitched up", [&] {
    const auto s = got_.last();
    return !s.moving() && s.pitch_ticks() > 1000;
  }));
  ASSERT_TRUE(Set({0, 0, 0}, 1).first);
  ASSERT_TRUE(WaitFor("the platform at rest at zero pitch", [&] {
    const auto s = got_.last();
    return !s.moving() && s.pitch_ticks() == 0;
  }));
  double camera_pitch = 0;
  host_->WithDevice([&](SimulatedDevice&) { camera_pitch = sim_->TrueDegrees()[1]; });
  EXPECT_NEAR(camera_pitch, 1.59 / 2, 1e-6);  // started at -1.59/2: back 1.59 degrees off

  ASSERT_TRUE(Set({5000, 0, 0}, 1).first);
  ASSERT_TRUE(WaitFor("the platform at rest at yaw 5000", [&] {
    const auto s = got_.last();
    return !s.moving() && s.yaw_ticks() == 5000;
  }));
  std::promise<std::pair<bool, std::string>> p;
  auto f = p.get_future();
  driver_->ResetZero([&p](bool ok, const std::string& m) { p.set_value({ok, m}); });
  ASSERT_TRUE(Wait(f).first);
  ASSERT_TRUE(WaitFor("yaw back at zero", [&] { return got_.last().yaw_ticks() == 0; }));
}

TEST_F(PlatformPty, CommandsFailCleanlyWhileThePortIsGoneAndWorkAfter) {
  host_->Vanish(std::chrono::milliseconds(500));
  ASSERT_TRUE(WaitFor("the port lost", [&] { return driver_->status().state() == REOPENING; }));
  auto [ok, message] = Set({100, 0, 0}, 1);
  EXPECT_FALSE(ok);
  EXPECT_NE(message.find("not connected"), std::string::npos);
  ASSERT_TRUE(WaitFor(
      "the port back", [&] { return driver_->status().state() == CONNECTED; },
      std::chrono::seconds(10)));
  ASSERT_TRUE(Set({100, 0, 0}, 1).first);
  ASSERT_TRUE(WaitFor("yaw at 100 ticks", [&] { return got_.last().yaw_ticks() == 100; }));
  host_->InjectGarbage(30);
  const size_t before = got_.size();
  ASSERT_TRUE(WaitFor("ten more readings", [&] { return got_.size() > before + 10; }));
  EXPECT_GE(driver_->status().garbage_bytes() + driver_->status().bad_frames(), 1u);
}

}  // namespace
}  // namespace igms::devices
