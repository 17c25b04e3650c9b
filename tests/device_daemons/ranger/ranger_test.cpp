#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <future>
#include <mutex>

#include "device_daemons/ranger/ranger_driver.h"
#include "device_daemons/ranger/ranger_scene.h"
#include "device_daemons/ranger/ranger_sim.h"
#include "device_daemons/ranger/udm_protocol.h"
#include "device_daemons/serial/pty_host.h"
#include "tests/device_daemons/test_util.h"

namespace igms::devices {
namespace {

std::optional<std::optional<double>> ParseOne(const std::string& bytes) {
  Frame7Parser p(udm::BodyLength);
  std::optional<std::optional<double>> out;
  for (char c : bytes) {
    if (p.Feed(static_cast<uint8_t>(c)) == ParseResult::kGood) out = udm::Decode(p.frame());
  }
  return out;
}

TEST(UdmProtocol, RangeAndNoEchoRoundTrip) {
  auto r = ParseOne(udm::EncodeRange(123.456));
  ASSERT_TRUE(r && *r);
  EXPECT_NEAR(**r, 123.46, 1e-9);
  EXPECT_EQ(udm::EncodeRange(123.456).size(), 5u);
  for (double bad : {1.0, 800.0, std::nan("")}) {
    r = ParseOne(udm::EncodeRange(bad));
    ASSERT_TRUE(r);
    EXPECT_FALSE(*r) << bad;
  }
  r = ParseOne(udm::EncodeRange(std::nullopt));
  ASSERT_TRUE(r);
  EXPECT_FALSE(*r);
}

TEST(RangerScene, BeamFindsTheNearestSurfaceInTheCone) {
  const RangerScene scene = RangerScene::Testbed();
  RangerPose pose;
  // Straight ahead: over the cylinder and the block, to the wall at 10 ft.
  auto r = BeamRange(scene, pose);
  ASSERT_TRUE(r);
  EXPECT_NEAR(*r, 120.0, 1e-9);
  // Looking 20 degrees down: the axis meets the cylinder's top at 52.6 in, but the beam
  // (+-6 degrees) also holds the top's near edge, at hypot(45, 18) = 48.47 in (21.8
  // degrees down); the sampled beam finds it within a fraction of an inch, never nearer.
  pose.pitch_deg = -20;
  r = BeamRange(scene, pose);
  ASSERT_TRUE(r);
  EXPECT_GE(*r, std::hypot(45.0, 18.0) - 1e-9);
  EXPECT_LT(*r, std::hypot(45.0, 18.0) + 0.2);
  // A narrow beam sees only the axis.
  r = BeamRange(scene, pose, 0.0);
  ASSERT_TRUE(r);
  EXPECT_NEAR(*r, 18.0 / std::sin(20 * M_PI / 180), 1e-6);
  // Looking up and away: nothing.
  pose.pitch_deg = 60;
  pose.yaw_deg = 180;
  EXPECT_FALSE(BeamRange(scene, pose));
}

TEST(RangerSim, AnswersOncePerMeasurementTime) {
  RangerSim sim;
  EXPECT_TRUE(sim.OnInput("RRR", 0).empty());  // one measurement under way
  int64_t wake = INT64_MAX;
  EXPECT_TRUE(sim.Poll(100'000'000, &wake).empty());
  EXPECT_EQ(wake, udm::kMeasureNs);
  const auto out = sim.Poll(170'000'000, &wake);
  ASSERT_EQ(out.size(), 1u);
  const auto r = ParseOne(out[0]);
  ASSERT_TRUE(r && *r);
  EXPECT_NEAR(**r, 120.0, 120.0 * 0.002 * 5);  // five sigma of the noise
  EXPECT_TRUE(sim.Poll(400'000'000, &wake).empty());
}

TEST(RangerPty, RangesOnRequestAtMost6HzAndSurvivesGarbage) {
  auto sim = std::make_unique<RangerSim>();
  RangerSim* raw = sim.get();
  PtyHost host(std::move(sim), {testing::TempPath("udm"), 9600});
  std::string error;
  ASSERT_TRUE(host.Start(&error)) << error;
  host.WithDevice([&](SimulatedDevice&) { raw->SetPose({Eigen::Vector3d::Zero(), 0, -20}); });
  testing::IoThread io;
  std::mutex mutex;
  std::vector<RangerState> got;
  RangerDriverOptions options;
  options.link.port = host.port();
  RangerDriver driver(io.io(), options, [&](const RangerState& s) {
    std::lock_guard lock(mutex);
    got.push_back(s);
  });
  driver.Start();
  // The probe taken on opening arrives.
  ASSERT_TRUE(testing::WaitFor([&] { std::lock_guard l(mutex); return !got.empty(); }));
  const auto range = [&] {
    std::promise<RangerState> p;
    auto f = p.get_future();
    driver.Range([&p](bool ok, const RangerState& s, const std::string&) {
      RangerState out = s;
      if (!ok) out.set_range_in(-1);
      p.set_value(out);
    });
    return f.get();
  };
  RangerState s = range();
  EXPECT_TRUE(s.valid());
  EXPECT_NEAR(s.range_in(), 48.5, 0.6);
  host.WithDevice([&](SimulatedDevice&) { raw->Override(std::nullopt); });
  s = range();
  EXPECT_FALSE(s.valid());
  host.WithDevice([&](SimulatedDevice&) { raw->Override(36.0); });
  host.InjectGarbage(20);
  s = range();
  EXPECT_DOUBLE_EQ(s.range_in(), 36.0);
  // Ten back-to-back requests take at least 9 measurement times.
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < 10; ++i) range();
  EXPECT_GE(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 9 * udm::kMeasureNs * 1e-9);
  driver.Stop();
  io.Stop();
}

TEST(RangerPty, ContinuousRangingAtTheFullRate) {
  PtyHost host(std::make_unique<RangerSim>(), {testing::TempPath("udm6"), 9600});
  std::string error;
  ASSERT_TRUE(host.Start(&error)) << error;
  testing::IoThread io;
  std::atomic<int> count{0};
  RangerDriverOptions options;
  options.link.port = host.port();
  options.poll_hz = 6;
  RangerDriver driver(io.io(), options, [&](const RangerState& s) {
    if (s.valid()) ++count;
  });
  driver.Start();
  ASSERT_TRUE(testing::WaitFor([&] { return count > 0; }));
  const int first = count;
  std::this_thread::sleep_for(std::chrono::seconds(2));
  const double rate = (count - first) / 2.0;
  EXPECT_GT(rate, 4.5);  // 6 less the wake-ups of a loaded machine
  EXPECT_LE(rate, 6.5);
  driver.Stop();
  io.Stop();
}

}  // namespace
}  // namespace igms::devices
