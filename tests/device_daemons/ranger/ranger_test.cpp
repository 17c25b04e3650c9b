#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <future>
#include <mutex>

#include "common/sim/ranger/site_ranger.h"
#include "common/sim/testbed.h"
#include "device_daemons/ranger/ranger_driver.h"
#include "device_daemons/ranger/ranger_sim.h"
#include "device_daemons/ranger/ranger_site.h"
#include "device_daemons/ranger/udm_protocol.h"
#include "device_daemons/serial/pty_host.h"
#include "tests/device_daemons/ranger/test_site.h"
#include "tests/support/files.h"
#include "tests/support/io_thread.h"
#include "tests/support/readings.h"
#include "tests/support/wait_for.h"

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

// The known site of test_site.h, loaded from files as the daemon loads it.
RangerWorld TestWorld() {
  const std::string scene = igms::testing::TempPath("scene.yaml"),
                    calib = igms::testing::TempPath("calib.yaml");
  igms::testing::WriteFile(scene, testing::TestSceneYaml());
  std::string error;
  EXPECT_TRUE(calibration::SaveCalibration(testing::TestCalibration(), calib, &error)) << error;
  auto world = LoadSiteRangerWorld(scene, calib);
  EXPECT_TRUE(world.ok()) << world.error();
  return *world;
}

TEST(RangerSite, MountFollowsThePlatformModel) {
  const RangerWorld world = TestWorld();
  // At the zero pose the calibration's end-frame mount is the world beam it was made from.
  RangerBeam beam = world.mount.BeamAt({});
  EXPECT_LT((beam.origin - testing::SensorAtZero()).norm(), 1e-9);
  EXPECT_LT((beam.axis - Eigen::Vector3d(0, -1, 0)).norm(), 1e-9);
  // Panned: the beam turns with the platform's world motion, about the pan axis.
  const auto q = testing::PanAngles(testing::kPanDeg);
  beam = world.mount.BeamAt(q);
  EXPECT_LT((beam.origin - testing::SensorAtZero()).norm(), 1e-9);
  EXPECT_NEAR(std::acos(beam.axis.dot(Eigen::Vector3d(0, -1, 0))), testing::kPanDeg * M_PI / 180,
              1e-9);
  EXPECT_NEAR(beam.axis.z(), 0.0, 1e-9);
  // A platform reading in encoder ticks goes through the model's tick scales.
  PlatformState reading;
  reading.set_yaw_ticks(
      static_cast<int32_t>(std::lround(testing::kPanDeg / geometry::ThesisPanDegreesPerTick())));
  const auto angles = world.mount.AnglesOf(reading);
  ASSERT_EQ(angles.size(), 3u);
  EXPECT_NEAR(angles[0], q[0], geometry::ThesisPanDegreesPerTick() * M_PI / 180);
}

TEST(RangerSite, BeamRangesTheNearestSurfaceOfTheScene) {
  const RangerWorld world = TestWorld();
  // Straight ahead: the box's near face, perpendicular to the beam.
  auto r = world.range(world.mount.BeamAt({}), udm::kBeamWidthDeg);
  ASSERT_TRUE(r);
  EXPECT_NEAR(*r, testing::kBoxRangeIn, 1e-9);
  // Panned: the sphere's nearest point.
  r = world.range(world.mount.BeamAt(testing::PanAngles(testing::kPanDeg)), udm::kBeamWidthDeg);
  ASSERT_TRUE(r);
  EXPECT_NEAR(*r, testing::kSphereRangeIn, 1e-6);
  // Half way between: the box is 4.8 degrees wide either side of straight ahead, so the
  // 6-degree half beam still meets its corner at 10 degrees of pan, not at 20.
  r = world.range(world.mount.BeamAt(testing::PanAngles(10)), udm::kBeamWidthDeg);
  ASSERT_TRUE(r);
  EXPECT_GT(*r, testing::kBoxRangeIn);
  EXPECT_LT(*r, 50.0);
  EXPECT_FALSE(world.range(world.mount.BeamAt(testing::PanAngles(20)), udm::kBeamWidthDeg));
  // The default: the thesis testbed, the sensor between its cameras, looking at the scene.
  const RangerBeam beam = TestbedRangerWorld().mount.BeamAt({});
  const auto cams = site::ThesisCameras();
  EXPECT_LT((beam.origin - 0.5 * (cams.left.Center() + cams.right.Center())).norm(), 1e-9);
  EXPECT_GT(beam.axis.dot(cams.left.ViewDirection()), 0.99);
}

TEST(RangerSite, BadFilesFailWithTheirNames) {
  const auto no_scene = LoadSiteRangerWorld("/nonexistent/scene.yaml", "");
  EXPECT_FALSE(no_scene.ok());
  EXPECT_NE(no_scene.error().find("/nonexistent/scene.yaml"), std::string::npos)
      << no_scene.error();
  const std::string bad = igms::testing::TempPath("bad.yaml");
  igms::testing::WriteFile(bad, "%YAML:1.0\n---\nleft: {P: [1, 2, 3]}\n");
  const auto bad_calibration = LoadSiteRangerWorld("", bad);
  EXPECT_FALSE(bad_calibration.ok());
  EXPECT_NE(bad_calibration.error().find("left.P"), std::string::npos) << bad_calibration.error();
}

TEST(RangerSite, TheWorldIsWhatTheProgramRegistered) {
  // The ranger's library links no site: without a registered world the simulator cannot start.
  RegisterRangerWorld(nullptr);
  const auto none = LoadRangerWorld("", "");
  EXPECT_FALSE(none.ok());
  EXPECT_NE(none.error().find("without the simulated site"), std::string::npos) << none.error();
  RegisterSiteRanger();
  auto world = LoadRangerWorld("", "");
  ASSERT_TRUE(world.ok()) << world.error();
  EXPECT_EQ(world->mount.BeamAt({}).origin, TestbedRangerWorld().mount.BeamAt({}).origin);
  // A simulator without a world hears no echo.
  RangerSim silent;
  EXPECT_FALSE(silent.TrueRange());
}

TEST(RangerSim, AnswersOncePerMeasurementTime) {
  RangerSimOptions options;
  options.world = TestWorld();
  RangerSim sim(options);
  EXPECT_TRUE(sim.OnInput("RRR", 0).empty());  // one measurement under way
  int64_t wake = INT64_MAX;
  EXPECT_TRUE(sim.Poll(100'000'000, &wake).empty());
  EXPECT_EQ(wake, udm::kMeasureNs);
  const auto out = sim.Poll(170'000'000, &wake);
  ASSERT_EQ(out.size(), 1u);
  const auto r = ParseOne(out[0]);
  ASSERT_TRUE(r && *r);
  EXPECT_NEAR(**r, testing::kBoxRangeIn, testing::kBoxRangeIn * 0.002 * 5);  // five sigma
  EXPECT_TRUE(sim.Poll(400'000'000, &wake).empty());
}

TEST(RangerPty, RangesOnRequestAtMost6HzAndSurvivesGarbage) {
  RangerSimOptions sim_options;
  sim_options.world = TestWorld();
  auto sim = std::make_unique<RangerSim>(sim_options);
  RangerSim* raw = sim.get();
  PtyHost host(std::move(sim), {igms::testing::TempPath("udm"), 9600});
  std::string error;
  ASSERT_TRUE(host.Start(&error)) << error;
  host.WithDevice(
      [&](SimulatedDevice&) { raw->SetJointAngles(testing::PanAngles(testing::kPanDeg)); });
  igms::testing::IoThread io;
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
  ASSERT_TRUE(igms::testing::WaitFor("the probe taken on opening", [&] {
    std::lock_guard l(mutex);
    return !got.empty();
  }));
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
  EXPECT_NEAR(s.range_in(), testing::kSphereRangeIn, 0.3);
  host.WithDevice([&](SimulatedDevice&) { raw->Override(std::nullopt); });
  s = range();
  EXPECT_FALSE(s.valid());
  host.WithDevice([&](SimulatedDevice&) { raw->Override(36.0); });
  host.InjectGarbage(20);
  s = range();
  EXPECT_DOUBLE_EQ(s.range_in(), 36.0);
  host.WithDevice([&](SimulatedDevice&) {
    raw->Release();
    raw->SetJointAngles({});
  });
  s = range();
  EXPECT_NEAR(s.range_in(), testing::kBoxRangeIn, 0.5);
  // Back-to-back requests wait for the measurement before: eleven readings span ten
  // measurement times on their own stamps (nine asserted: a stamp may be taken late).
  std::vector<RangerState> eleven;
  eleven.reserve(11);
  for (int i = 0; i < 11; ++i) eleven.push_back(range());
  EXPECT_GE(
      eleven.back().stamp().receive_monotonic_ns() - eleven.front().stamp().receive_monotonic_ns(),
      9 * udm::kMeasureNs);
  driver.Stop();
  io.Stop();
}

TEST(RangerPty, ContinuousRangingAtTheFullRate) {
  RangerSimOptions testbed;
  testbed.world = TestbedRangerWorld();
  PtyHost host(std::make_unique<RangerSim>(testbed), {igms::testing::TempPath("udm6"), 9600});
  std::string error;
  ASSERT_TRUE(host.Start(&error)) << error;
  igms::testing::IoThread io;
  igms::testing::Collected<RangerState> got;
  RangerDriverOptions options;
  options.link.port = host.port();
  options.poll_hz = 6;
  RangerDriver driver(io.io(), options, got.Sink());
  driver.Start();
  ASSERT_TRUE(igms::testing::WaitFor("a first range", [&] { return got.size() > 0; }));
  // Two seconds of ranging, paced on the readings' own stamps: 6 a second, never more.
  const double rate = got.StampedRate(12);
  EXPECT_GT(rate, 4.5);
  EXPECT_LE(rate, 6.5);
  EXPECT_TRUE(got.last().valid());
  driver.Stop();
  io.Stop();
}

}  // namespace
}  // namespace igms::devices
