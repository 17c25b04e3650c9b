// Every daemon as a real process with its simulator on a real pseudo-terminal, through a
// real TCP subscriber: values, rates, faults, commands, record and replay, bad input.
#include <gtest/gtest.h>
#include <linux/joystick.h>
#include <sys/stat.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>

#include "common/base/clock.h"
#include "common/net/client.h"
#include "device_daemons/joystick/gamepad.h"
#include "device_daemons/serial/recording.h"
#include "igms/devices.pb.h"
#include "tests/device_daemons/ranger/test_site.h"
#include "tests/support/child_process.h"
#include "tests/support/daemon_process.h"
#include "tests/support/files.h"
#include "tests/support/io_thread.h"
#include "tests/support/readings.h"
#include "tests/support/wait_for.h"

namespace igms::devices {
namespace {

using igms::testing::IoThread;
using igms::testing::WaitFor;
using testing::DaemonProcess;
using namespace std::chrono_literals;

// A subscriber's readings; rates are measured on the stamps the daemon put in them.
template <class Msg>
using Stream = igms::testing::Collected<Msg>;

class Connected {
 public:
  explicit Connected(uint16_t port) {
    net::ClientOptions o;
    o.port = port;
    o.name = "daemons_test";
    client_ = std::make_unique<net::Client>(io_.io(), o);
    client_->Start();
  }
  ~Connected() {
    client_->Stop();
    io_.Stop();
  }
  net::Client& operator*() { return *client_; }
  net::Client* operator->() { return client_.get(); }

 private:
  IoThread io_;
  std::unique_ptr<net::Client> client_;
};

net::Status Inject(net::Client& c, const SimInjectRequest& req) {
  return c.CallSync<SimInjectResponse>("igms.devices.SimService.Inject", req, 2s).status;
}

LinkStatus StatusOf(net::Client& c, const std::string& service) {
  return c.CallSync<LinkStatus>(service + ".Status", GetStatusRequest(), 2s).value;
}

TEST(JoystickDaemon, ReadingsFaultsRecordAndReplay) {
  const std::string recording = igms::testing::TempPath("joy.rec");
  std::vector<Reading> recorded;
  {
    DaemonProcess daemon("igms-joystickd", {"--simulate", "--port", "0", "--record", recording});
    const uint16_t port = daemon.WaitForPort();
    ASSERT_NE(port, 0) << daemon.Log();
    Connected client(port);
    SimInjectRequest req;
    req.mutable_joystick()->set_x(0.5);
    req.mutable_joystick()->set_twist(-0.75);
    req.mutable_joystick()->set_buttons(0x04);  // button 3: remove model (table 2.2)
    req.mutable_joystick()->set_trigger(true);
    ASSERT_TRUE(
        WaitFor("the sim service to take the stick", [&] { return Inject(*client, req).ok(); }));

    Stream<JoystickState> all, slow;
    SubscribeRequest full, ten;
    ten.set_rate_hz(10);
    client->Subscribe<JoystickState>("igms.devices.JoystickService.Live", full, all.Sink());
    client->Subscribe<JoystickState>("igms.devices.JoystickService.Live", ten, slow.Sink());
    ASSERT_TRUE(WaitFor("readings with the injected stick",
                        [&] { return all.size() > 5 && std::abs(all.last().x() - 0.5) < 1e-3; }));
    // A second of each stream, paced on the readings' stamps. 50 polls a second nearly fill
    // the 9600-baud line, so a loaded machine's late polls are not all made up: the bound
    // below 50 is wider than above.
    const double rate = all.StampedRate(50);
    EXPECT_GT(rate, 35.0);
    EXPECT_LT(rate, 55.0);
    ASSERT_TRUE(WaitFor("the 10 Hz stream's first reading", [&] { return slow.size() > 0; }));
    EXPECT_NEAR(slow.StampedRate(10), 10.0, 2.5);
    const JoystickState s = all.last();
    EXPECT_NEAR(s.twist(), -0.75, 1e-3);
    EXPECT_EQ(s.buttons(), 0x04u);
    EXPECT_TRUE(s.trigger());

    // Garbage and a truncated report: counted, readings go on.
    SimInjectRequest fault;
    fault.mutable_fault()->set_garbage_bytes(64);
    fault.mutable_fault()->set_truncate_next(true);
    ASSERT_TRUE(Inject(*client, fault).ok());
    ASSERT_TRUE(WaitFor("the bad frame or garbage counted", [&] {
      const LinkStatus st = StatusOf(*client, "igms.devices.JoystickService");
      return st.bad_frames() + st.garbage_bytes() > 0;
    }));
    // The port vanishes and returns: the daemon reopens and the stream resumes.
    SimInjectRequest vanish;
    vanish.mutable_fault()->set_vanish_ms(400);
    ASSERT_TRUE(Inject(*client, vanish).ok());
    ASSERT_TRUE(WaitFor("the port reopened", [&] {
      return StatusOf(*client, "igms.devices.JoystickService").reopens() >= 1;
    }));
    const size_t before = all.size();
    ASSERT_TRUE(WaitFor(
        "20 readings after reopening", [&] { return all.size() > before + 20; }, 15s));
    EXPECT_EQ(StatusOf(*client, "igms.devices.JoystickService").state(), CONNECTED);

    // Bad input to the sim service: a clear error, nothing breaks.
    SimInjectRequest wrong;
    wrong.mutable_viewer()->set_x_m(1);
    const net::Status st = Inject(*client, wrong);
    EXPECT_EQ(st.code, igms::BAD_REQUEST);
    EXPECT_NE(st.message.find("JoystickState"), std::string::npos);
    EXPECT_EQ(daemon.Stop(), 0);
  }
  auto rec = LoadRecording(recording);
  ASSERT_TRUE(rec.ok()) << rec.error();
  EXPECT_EQ(rec->header.device(), "joystick");
  ASSERT_GT(rec->readings.size(), 100u);

  // Replayed four times faster: the same readings, in order.
  DaemonProcess replay("igms-joystickd",
                       {"--replay", recording, "--replay-speed", "4", "--port", "0"});
  const uint16_t port = replay.WaitForPort();
  ASSERT_NE(port, 0) << replay.Log();
  Connected client(port);
  Stream<JoystickState> got;
  client->Subscribe<JoystickState>("igms.devices.JoystickService.Live", SubscribeRequest(),
                                   got.Sink());
  ASSERT_TRUE(WaitFor("40 replayed readings", [&] { return got.size() >= 40; }));
  {
    // Each replayed reading is the recorded one with its sequence number, in order. The
    // stream keeps only the newest unsent reading, so a few may be skipped, not altered.
    std::lock_guard lock(got.mutex);
    std::map<uint64_t, const JoystickState*> by_sequence;
    for (const Reading& r : rec->readings)
      by_sequence[r.joystick().stamp().sequence()] = &r.joystick();
    uint64_t previous = 0;
    for (const JoystickState& g : got.readings) {
      const auto it = by_sequence.find(g.stamp().sequence());
      ASSERT_NE(it, by_sequence.end())
          << "sequence " << g.stamp().sequence() << " was never recorded";
      EXPECT_GT(g.stamp().sequence(), previous);
      previous = g.stamp().sequence();
      EXPECT_DOUBLE_EQ(g.x(), it->second->x());
      EXPECT_DOUBLE_EQ(g.twist(), it->second->twist());
      EXPECT_EQ(g.trigger(), it->second->trigger());
    }
    const uint64_t span =
        got.readings.back().stamp().sequence() - got.readings.front().stamp().sequence() + 1;
    EXPECT_GE(got.readings.size(), span / 2);  // a loaded machine's subscriber skips more
  }
  EXPECT_EQ(StatusOf(*client, "igms.devices.JoystickService").state(), REPLAYING);
  EXPECT_EQ(replay.Stop(), 0);
  std::filesystem::remove(recording);
}

TEST(ViewerDaemon, InjectedPoseAndButtonsAt70Hz) {
  DaemonProcess daemon("igms-viewerd", {"--simulate", "--port", "0"});
  const uint16_t port = daemon.WaitForPort();
  ASSERT_NE(port, 0) << daemon.Log();
  Connected client(port);
  SimInjectRequest req;
  ViewerState* v = req.mutable_viewer();
  v->set_x_m(0.3);
  v->set_y_m(-0.2);
  v->set_yaw_deg(-120);
  v->set_pitch_deg(15);
  v->set_button_left(true);
  v->set_button_right(true);  // table 2.1: 11, slave to the viewer
  ASSERT_TRUE(
      WaitFor("the sim service to take the pose", [&] { return Inject(*client, req).ok(); }));
  Stream<ViewerState> all;
  client->Subscribe<ViewerState>("igms.devices.ViewerService.Live", SubscribeRequest(), all.Sink());
  ASSERT_TRUE(WaitFor("readings with the injected buttons",
                      [&] { return all.size() > 5 && all.last().button_left(); }));
  // A second of the stream, timed by the readings' stamps.
  EXPECT_GT(all.StampedRate(70), 56.0);
  const ViewerState s = all.last();
  EXPECT_NEAR(s.x_m(), 0.3, 0.0005);
  EXPECT_NEAR(s.y_m(), -0.2, 0.0005);
  EXPECT_NEAR(s.yaw_deg(), -120, 0.05);
  EXPECT_NEAR(s.pitch_deg(), 15, 0.05);
  EXPECT_TRUE(s.button_right());
  EXPECT_GT(s.stamp().receive_unix_ns(), 0);
  EXPECT_EQ(daemon.Stop(), 0);
}

// SimInjectRequest.viewer_buttons sets the two buttons alone: a steady pose stays where it
// was, and a path goes on moving.
TEST(ViewerDaemon, InjectedButtonsLeaveThePoseAlone) {
  {
    DaemonProcess daemon("igms-viewerd", {"--simulate", "--port", "0"});
    const uint16_t port = daemon.WaitForPort();
    ASSERT_NE(port, 0) << daemon.Log();
    Connected client(port);
    SimInjectRequest pose;
    pose.mutable_viewer()->set_x_m(0.3);
    pose.mutable_viewer()->set_yaw_deg(-120);
    pose.mutable_viewer()->set_button_left(true);
    pose.mutable_viewer()->set_button_right(true);
    ASSERT_TRUE(WaitFor("the pose injected", [&] { return Inject(*client, pose).ok(); }));
    Stream<ViewerState> all;
    client->Subscribe<ViewerState>("igms.devices.ViewerService.Live", SubscribeRequest(),
                                   all.Sink());
    ASSERT_TRUE(WaitFor("a reading with the left button",
                        [&] { return all.size() > 0 && all.last().button_left(); }));
    SimInjectRequest buttons;
    buttons.mutable_viewer_buttons()->set_button_right(true);  // table 2.1: 01, freeze
    ASSERT_TRUE(Inject(*client, buttons).ok());
    ASSERT_TRUE(
        WaitFor("a reading without the left button", [&] { return !all.last().button_left(); }));
    const ViewerState s = all.last();
    EXPECT_TRUE(s.button_right());
    EXPECT_NEAR(s.x_m(), 0.3, 0.0005);
    EXPECT_NEAR(s.yaw_deg(), -120, 0.05);
    EXPECT_EQ(daemon.Stop(), 0);
  }
  // A head turning 90 degrees in 10 s and back.
  const std::string path = igms::testing::TempPath("turn.path");
  igms::testing::WriteFile(path, "0 0 0 0 0 0 0\n10 0 0 0 90 0 0\n20 0 0 0 0 0 0\n");
  DaemonProcess daemon("igms-viewerd", {"--simulate", "--port", "0", "--path", path});
  const uint16_t port = daemon.WaitForPort();
  ASSERT_NE(port, 0) << daemon.Log();
  Connected client(port);
  Stream<ViewerState> all;
  client->Subscribe<ViewerState>("igms.devices.ViewerService.Live", SubscribeRequest(), all.Sink());
  SimInjectRequest buttons;
  buttons.mutable_viewer_buttons()->set_button_left(true);
  ASSERT_TRUE(WaitFor("the buttons injected", [&] { return Inject(*client, buttons).ok(); }));
  ASSERT_TRUE(WaitFor("a reading with the left button",
                      [&] { return all.size() > 0 && all.last().button_left(); }));
  const double yaw = all.last().yaw_deg();
  ASSERT_TRUE(WaitFor("the yaw moved", [&] { return std::abs(all.last().yaw_deg() - yaw) > 1.0; }))
      << "the path stopped";
  EXPECT_TRUE(all.last().button_left());
  EXPECT_FALSE(all.last().button_right());
  EXPECT_EQ(daemon.Stop(), 0);
  std::filesystem::remove(path);
}

// The simulator as a pose tracker of the site: powered up 1 m along the site's x, turned
// 90 degrees left, a head pose in the site is reported relative to that.
TEST(ViewerDaemon, ReportsHeadPosesInTheSiteRelativeToPowerUp) {
  DaemonProcess daemon("igms-viewerd", {"--simulate", "--port", "0", "--power-up", "1 0 0 90 0 0"});
  const uint16_t port = daemon.WaitForPort();
  ASSERT_NE(port, 0) << daemon.Log();
  Connected client(port);
  SimInjectRequest req;
  ViewerState* v = req.mutable_viewer();
  v->set_x_m(1.0);
  v->set_y_m(0.25);    // 0.25 m forward of the power-up pose
  v->set_yaw_deg(60);  // 30 degrees right of it
  v->set_button_left(true);
  ASSERT_TRUE(
      WaitFor("the sim service to take the pose", [&] { return Inject(*client, req).ok(); }));
  Stream<ViewerState> all;
  client->Subscribe<ViewerState>("igms.devices.ViewerService.Live", SubscribeRequest(), all.Sink());
  ASSERT_TRUE(WaitFor("readings with the injected button",
                      [&] { return all.size() > 5 && all.last().button_left(); }));
  const ViewerState s = all.last();
  EXPECT_NEAR(s.x_m(), 0.25, 0.0005);
  EXPECT_NEAR(s.y_m(), 0.0, 0.0005);
  EXPECT_NEAR(s.yaw_deg(), -30, 0.05);
  EXPECT_EQ(daemon.Stop(), 0);
  DaemonProcess bad("igms-viewerd", {"--simulate", "--port", "0", "--power-up", "1 2 3"});
  EXPECT_EQ(bad.WaitExit(), 2);
  EXPECT_NE(bad.Log().find("power-up pose takes 6 numbers"), std::string::npos) << bad.Log();
}

TEST(PlatformDaemon, SetOrientationResetZeroAndBadRequests) {
  DaemonProcess daemon("igms-platformd", {"--simulate", "--port", "0", "--backlash-deg", "1.59"});
  const uint16_t port = daemon.WaitForPort();
  ASSERT_NE(port, 0) << daemon.Log();
  Connected client(port);
  Stream<PlatformState> all;
  client->Subscribe<PlatformState>("igms.devices.PlatformService.Live", SubscribeRequest(),
                                   all.Sink());
  ASSERT_TRUE(WaitFor("the first readings", [&] { return all.size() > 3; }));
  SetOrientationRequest set;
  set.set_yaw_ticks(8142);    // 30 degrees
  set.set_pitch_ticks(-286);  // -5 degrees
  set.set_steps_per_move(40);
  auto r = client->CallSync<SetOrientationResponse>("igms.devices.PlatformService.SetOrientation",
                                                    set, 3s);
  ASSERT_TRUE(r.ok()) << r.status.ToString();
  ASSERT_TRUE(WaitFor("the platform at rest at yaw 8142", [&] {
    const auto s = all.last();
    return !s.moving() && s.yaw_ticks() == 8142;
  }));
  EXPECT_EQ(all.last().pitch_ticks(), -286);
  EXPECT_NEAR(all.last().yaw_deg(), 30.0, 0.01);

  auto z = client->CallSync<ResetZeroResponse>("igms.devices.PlatformService.ResetZero",
                                               ResetZeroRequest(), 3s);
  ASSERT_TRUE(z.ok()) << z.status.ToString();
  ASSERT_TRUE(WaitFor("the pose reset to zero", [&] {
    return all.last().yaw_ticks() == 0 && all.last().pitch_ticks() == 0;
  }));

  set.set_yaw_ticks(5'000'000);
  r = client->CallSync<SetOrientationResponse>("igms.devices.PlatformService.SetOrientation", set,
                                               3s);
  EXPECT_EQ(r.status.code, igms::BAD_REQUEST);
  SimInjectRequest joy;
  joy.mutable_joystick();
  EXPECT_EQ(Inject(*client, joy).code, igms::BAD_REQUEST);
  EXPECT_EQ(daemon.Stop(), 0);
}

// A port nobody listens on now, for a process that must be named before it starts.
uint16_t FreePort() {
  boost::asio::io_context io;
  boost::asio::ip::tcp::acceptor a(io, {boost::asio::ip::make_address("127.0.0.1"), 0});
  return a.local_endpoint().port();
}

// The lab's way: the ranger's section names the platform process; the ranger starts
// first and its subscription reconnects once the platform daemon is up.
TEST(RangerDaemon, RangesTheSiteAndTurnsWithThePlatform) {
  const std::string scene = igms::testing::TempPath("scene.yaml"),
                    calib = igms::testing::TempPath("calib.yaml");
  const std::string lab = igms::testing::TempPath("lab.yaml");
  igms::testing::WriteFile(scene, testing::TestSceneYaml());
  std::string error;
  ASSERT_TRUE(calibration::SaveCalibration(testing::TestCalibration(), calib, &error)) << error;
  const uint16_t platform_port = FreePort();
  igms::testing::WriteFile(
      lab, "lab: {token: \"\", calibration: " + calib +
               "}\n"
               "processes:\n"
               "  platform: {program: igms-platformd, host: 127.0.0.1, port: " +
               std::to_string(platform_port) +
               ", serial: simulate}\n"
               "  ranger: {program: igms-rangerd, host: 127.0.0.1, port: 0, serial: simulate,\n"
               "           platform: platform, scene: " +
               scene + ", poll_hz: 6}\n");
  DaemonProcess ranger("igms-rangerd", {"--config", lab, "--name", "ranger"});
  const uint16_t port = ranger.WaitForPort();
  ASSERT_NE(port, 0) << ranger.Log();
  Connected client(port);
  Stream<RangerState> live;
  client->Subscribe<RangerState>("igms.devices.RangerService.Live", SubscribeRequest(),
                                 live.Sink());
  // The mean of six streamed readings, after the ones before `since`.
  const auto mean_range = [&](size_t since) {
    EXPECT_TRUE(WaitFor("six more ranges", [&] { return live.size() >= since + 6; }));
    std::lock_guard lock(live.mutex);
    double sum = 0;
    for (size_t i = live.readings.size() - 6; i < live.readings.size(); ++i) {
      EXPECT_TRUE(live.readings[i].valid());
      sum += live.readings[i].range_in();
    }
    return sum / 6;
  };
  // No platform yet: the zero pose, the box straight ahead.
  EXPECT_NEAR(mean_range(0), testing::kBoxRangeIn, 0.15);
  EXPECT_NEAR(live.StampedRate(6), 6.0, 1.5);  // a second of ranging, on the stamps
  // The platform comes up and pans: the beam leaves the box and meets the sphere.
  DaemonProcess platform("igms-platformd", {"--config", lab, "--name", "platform"});
  ASSERT_EQ(platform.WaitForPort(), platform_port) << platform.Log();
  Connected platform_client(platform_port);
  SetOrientationRequest pan;
  pan.set_yaw_ticks(
      static_cast<int32_t>(std::lround(testing::kPanDeg / geometry::ThesisPanDegreesPerTick())));
  ASSERT_TRUE(WaitFor("the platform daemon to take the pan", [&] {
    return platform_client
        ->CallSync<SetOrientationResponse>("igms.devices.PlatformService.SetOrientation", pan, 3s)
        .ok();
  }));
  ASSERT_TRUE(WaitFor(
      "the beam on the sphere",
      [&] { return std::abs(live.last().range_in() - testing::kSphereRangeIn) < 0.3; }, 20s))
      << live.last().DebugString() << ranger.Log();
  EXPECT_NEAR(mean_range(live.size()), testing::kSphereRangeIn, 0.1);
  // On request too, through the same serial path.
  auto r = client->CallSync<RangerState>("igms.devices.RangerService.Range", RangeRequest(), 3s);
  ASSERT_TRUE(r.ok()) << r.status.ToString();
  EXPECT_NEAR(r.value.range_in(), testing::kSphereRangeIn, 0.3);
  // The platform daemon goes away: the ranger keeps its last pose and keeps ranging.
  EXPECT_EQ(platform.Stop(), 0);
  EXPECT_NEAR(mean_range(live.size()), testing::kSphereRangeIn, 0.1);
  // The sim service sets the pose too; a fixed answer overrides the site, and ends.
  SimInjectRequest home;
  home.mutable_platform()->set_yaw_ticks(0);
  ASSERT_TRUE(Inject(*client, home).ok());
  ASSERT_TRUE(WaitFor("the beam back on the box", [&] {
    return std::abs(live.last().range_in() - testing::kBoxRangeIn) < 0.5;
  }));
  SimInjectRequest none;
  none.mutable_ranger()->set_valid(false);
  ASSERT_TRUE(Inject(*client, none).ok());
  ASSERT_TRUE(WaitFor("an invalid range", [&] { return !live.last().valid(); }));
  SimInjectRequest release;
  release.mutable_ranger()->set_valid(true);
  ASSERT_TRUE(Inject(*client, release).ok());
  ASSERT_TRUE(WaitFor("a valid range again", [&] { return live.last().valid(); }));
  EXPECT_EQ(ranger.Stop(), 0);
}

TEST(RangerDaemon, BadSiteFilesFailWithAMessage) {
  DaemonProcess ranger("igms-rangerd",
                       {"--simulate", "--port", "0", "--scene", "/nonexistent/site.yaml"});
  EXPECT_NE(ranger.WaitExit(), 0);
  EXPECT_NE(ranger.Log().find("/nonexistent/site.yaml"), std::string::npos) << ranger.Log();
}

// A Linux joystick as the FlyBox's stand-in, through real file descriptors: a FIFO the test
// writes js_event records into, read by the real daemon, checked through a real TCP
// subscriber; the lab configuration names the device and overrides the mapping.
class JsWriter {
 public:
  explicit JsWriter(const std::string& path) {
    // Non-blocking open fails (ENXIO) until the daemon has the FIFO open for reading.
    igms::testing::WaitUntil(
        [&] { return (fd_ = ::open(path.c_str(), O_WRONLY | O_NONBLOCK)) >= 0; }, 15s);
  }
  ~JsWriter() { Close(); }
  bool ok() const { return fd_ >= 0; }
  void Send(uint8_t type, uint8_t number, int16_t value) {
    const std::string e = EncodeJsEvent(++time_ms_, value, type, number);
    ASSERT_EQ(::write(fd_, e.data(), e.size()), static_cast<ssize_t>(e.size()));
  }
  void Close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_ = -1;
  uint32_t time_ms_ = 1000;
};

TEST(JoystickDaemon, GamepadFromTheLabConfigurationPublishesFlyBoxReadings) {
  const std::string fifo = igms::testing::TempPath("js0"),
                    lab = igms::testing::TempPath("lab.yaml");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // Lab configuration: simulate by default, but the gamepad picked; trigger moved to
  // device button 7 and FlyBox button 1 to device button 0.
  igms::testing::WriteFile(
      lab,
      "processes:\n"
      "  joystick: {program: igms-joystickd, host: 127.0.0.1, port: 0, serial: simulate,\n"
      "             gamepad: " +
          fifo +
          ",\n"
          "             gamepad_map: {trigger: 7, buttons: [0, 2, 3, 4, 5, 6, 8, 9]}}\n");
  DaemonProcess daemon("igms-joystickd", {"--config", lab, "--name", "joystick"});
  const uint16_t port = daemon.WaitForPort();
  ASSERT_NE(port, 0) << daemon.Log();
  Connected client(port);
  Stream<JoystickState> live;
  client->Subscribe<JoystickState>("igms.devices.JoystickService.Live", SubscribeRequest(),
                                   live.Sink());
  {
    JsWriter js(fifo);
    ASSERT_TRUE(js.ok()) << daemon.Log();
    for (uint8_t a = 0; a < 6; ++a) js.Send(JS_EVENT_AXIS | JS_EVENT_INIT, a, 0);
    for (uint8_t b = 0; b < 10; ++b) js.Send(JS_EVENT_BUTTON | JS_EVENT_INIT, b, 0);
    js.Send(JS_EVENT_AXIS, 1, -16384);  // forward, half
    js.Send(JS_EVENT_AXIS, 3, 32767);   // twist right
    js.Send(JS_EVENT_BUTTON, 0, 1);     // FlyBox button 1 (remapped)
    js.Send(JS_EVENT_BUTTON, 7, 1);     // trigger (remapped)
    ASSERT_TRUE(WaitFor("a reading with the trigger pulled", [&] {
      return live.size() > 0 && live.last().trigger();
    })) << daemon.Log();
    const JoystickState s = live.last();
    EXPECT_NEAR(s.x(), 0.5, 1e-3);
    EXPECT_NEAR(s.twist(), 1.0, 1e-9);
    EXPECT_EQ(s.buttons(), 1u);
    EXPECT_EQ(s.stamp().device_time_us(), 1020u * 1000);
    // The FlyBox's rate while the stick is held still: 50 a second, on the readings' stamps.
    // Each tick is timed from the reading before, so a loaded machine's late wake-ups
    // lengthen every interval a little: the bound below 50 is wider than above.
    ASSERT_TRUE(WaitFor("a reading at rest", [&] { return live.size() > 0; }));
    const double rate = live.StampedRate(50);
    EXPECT_GT(rate, 35.0);
    EXPECT_LT(rate, 55.0);
    const LinkStatus st = StatusOf(*client, "igms.devices.JoystickService");
    EXPECT_EQ(st.state(), CONNECTED);
    EXPECT_EQ(st.port(), fifo);
    js.Send(JS_EVENT_BUTTON, 7, 0);
    ASSERT_TRUE(WaitFor("the trigger released", [&] { return !live.last().trigger(); }));
  }  // the writer closes: the device vanished
  ASSERT_TRUE(WaitFor("the gamepad reported gone", [&] {
    return StatusOf(*client, "igms.devices.JoystickService").state() != CONNECTED;
  }));
  const int64_t gone_ns = MonotonicNs();
  LinkStatus st = StatusOf(*client, "igms.devices.JoystickService");
  EXPECT_NE(st.message().find(fifo), std::string::npos) << st.DebugString();
  // The daemon reopens the FIFO and waits there for a writer; nothing is published while
  // the device is gone: no reading is stamped between then and its return.
  ASSERT_TRUE(WaitFor("the FIFO reopened, with no writer yet", [&] {
    return StatusOf(*client, "igms.devices.JoystickService").reopens() >= 1;
  }));
  const size_t before = live.size();
  const int64_t back_ns = MonotonicNs();
  // It comes back: reopened, the stream resumes with the state it reports.
  JsWriter js(fifo);
  ASSERT_TRUE(js.ok());
  js.Send(JS_EVENT_AXIS | JS_EVENT_INIT, 0, 32767);
  ASSERT_TRUE(WaitFor(
      "readings of the returned gamepad",
      [&] { return live.size() > before + 5 && std::abs(live.last().y() - 1.0) < 1e-9; }, 15s));
  {
    std::lock_guard lock(live.mutex);
    for (const JoystickState& r : live.readings) {
      const int64_t t = r.stamp().receive_monotonic_ns();
      EXPECT_FALSE(t >= gone_ns && t < back_ns) << "published while gone: " << r.DebugString();
    }
  }
  st = StatusOf(*client, "igms.devices.JoystickService");
  EXPECT_EQ(st.state(), CONNECTED);
  EXPECT_GE(st.reopens(), 1u);
  EXPECT_NEAR(live.last().x(), 0.0, 1e-9);  // a reopened device reports afresh
  // The sim service has nothing to drive.
  SimInjectRequest req;
  req.mutable_joystick()->set_x(0.5);
  EXPECT_EQ(Inject(*client, req).code, igms::UNAVAILABLE);
  EXPECT_EQ(daemon.Stop(), 0);
}

TEST(JoystickDaemon, BadGamepadMappingFailsWithAMessage) {
  const std::string lab = igms::testing::TempPath("lab.yaml");
  igms::testing::WriteFile(
      lab, "processes:\n  joystick: {port: 0, gamepad: /dev/null, gamepad_map: {axes: [1, 2]}}\n");
  DaemonProcess daemon("igms-joystickd", {"--config", lab, "--name", "joystick"});
  EXPECT_EQ(daemon.WaitExit(), 2);
  EXPECT_NE(daemon.Log().find("gamepad_map.axes"), std::string::npos) << daemon.Log();
}

// A relative path in the lab file is relative to the file's folder (docs/configuration.md),
// not to the daemon's working folder.
TEST(Daemons, RecordKeyIsRelativeToTheLabFile) {
  igms::testing::ScratchDir dir;
  const std::string lab = dir.File("lab.yaml");
  igms::testing::WriteFile(
      lab, "processes:\n  platform: {port: 0, serial: simulate, record: platform.rec}\n");
  DaemonProcess daemon("igms-platformd", {"--config", lab, "--name", "platform"});
  ASSERT_NE(daemon.WaitForPort(), 0) << daemon.Log();
  EXPECT_TRUE(WaitFor("the recording beside the lab file", [&] {
    return std::filesystem::exists(dir.File("platform.rec"));
  })) << daemon.Log();
  EXPECT_EQ(daemon.Stop(), 0);
}

TEST(Daemons, BadCommandLinesFailWithAMessage) {
  DaemonProcess none("igms-joystickd", {"--port", "0"});
  EXPECT_EQ(none.WaitExit(), 2);
  EXPECT_NE(none.Log().find("--serial PORT, --simulate or --replay FILE"), std::string::npos)
      << none.Log();
  DaemonProcess two("igms-viewerd", {"--simulate", "--replay", "x.rec"});
  EXPECT_EQ(two.WaitExit(), 2);
  DaemonProcess missing("igms-platformd", {"--replay", "/nonexistent/file.rec", "--port", "0"});
  EXPECT_EQ(missing.WaitExit(), 1);
  EXPECT_NE(missing.Log().find("cannot open recording"), std::string::npos) << missing.Log();
  DaemonProcess path("igms-viewerd",
                     {"--simulate", "--path", "/nonexistent/path.txt", "--port", "0"});
  EXPECT_EQ(path.WaitExit(), 1);
}

}  // namespace
}  // namespace igms::devices
