// The session's state machine (Cooke, section 2.4, figure 2-5), driven by events with stamps;
// each test asserts the effects that come out.
#include "control/session/session.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "control/session/cues.h"
#include "tests/control/session/thesis_calibration.h"

namespace igms::control {
namespace {

constexpr int64_t kMs = 1'000'000;

template <class T>
std::vector<T> All(const Effects& effects) {
  std::vector<T> out;
  for (const Effect& e : effects)
    if (const T* t = std::get_if<T>(&e)) out.push_back(*t);
  return out;
}

template <class T>
bool Has(const Effects& effects) {
  return !All<T>(effects).empty();
}

std::vector<std::string> Sounds(const Effects& effects) {
  std::vector<std::string> keys;
  for (const auto& s : All<PlaySoundEffect>(effects)) keys.push_back(s.key);
  return keys;
}

std::vector<devices::OperatorState> States(const Effects& effects) {
  std::vector<devices::OperatorState> out;
  for (const auto& s : All<SetOperatorStateEffect>(effects)) out.push_back(s.state);
  return out;
}

std::string Notices(const Effects& effects) {
  std::string text;
  for (const auto& n : All<NoticeEffect>(effects)) text += n.text + "\n";
  return text;
}

class SessionTest : public ::testing::Test {
 protected:
  void SetUp() override { Make(SessionOptions{}); }

  void Make(const SessionOptions& options) {
    calibration_ = testing::ThesisCalibration();
    std::string why;
    session_ = Session::Make(options, calibration_, &why);
    ASSERT_TRUE(session_) << why;
  }

  Effects Send(const Event& e) { return session_->Handle(e); }

  StartEvent AllUp() {
    StartEvent start;
    int port = 7300;
    for (Peer p : kAllPeers)
      start.peers.push_back({p, "127.0.0.1:" + std::to_string(port++), true, ""});
    start.now_ns = now_;
    return start;
  }

  // Starts with every peer up and lets the welcome play.
  void Start() {
    Send(AllUp());
    now_ += 2000 * kMs;
    Send(TickEvent{now_});
    ASSERT_EQ(session_->mode(), Mode::kVerification);
  }

  Effects Command(CommandKind kind, CommandSource source = CommandSource::kKeyboard) {
    now_ += 10 * kMs;
    return Send(CommandEvent{{kind, source, now_}, now_});
  }

  Effects Viewer(double yaw, double pitch = 0, double roll = 0, bool left = false,
                 bool right = false) {
    now_ += 14 * kMs;
    devices::ViewerState v;
    v.mutable_stamp()->set_sequence(++viewer_sequence_);
    v.mutable_stamp()->set_receive_monotonic_ns(now_);
    v.set_yaw_deg(yaw);
    v.set_pitch_deg(pitch);
    v.set_roll_deg(roll);
    v.set_button_left(left);
    v.set_button_right(right);
    return Send(ViewerReading{v, now_});
  }

  Effects Platform(bool moving, const PlatformTicks& at = {}) {
    now_ += 20 * kMs;
    devices::PlatformState p;
    p.mutable_stamp()->set_sequence(++platform_sequence_);
    p.set_yaw_ticks(at.yaw);
    p.set_pitch_ticks(at.pitch);
    p.set_moving(moving);
    return Send(PlatformReading{p, now_});
  }

  Effects Joystick(double x, double y, double twist, uint32_t buttons, bool trigger,
                   int64_t step_ns = 20 * kMs) {
    now_ += step_ns;
    devices::JoystickState j;
    j.mutable_stamp()->set_sequence(++joystick_sequence_);
    j.mutable_stamp()->set_receive_monotonic_ns(now_);
    j.set_x(x);
    j.set_y(y);
    j.set_twist(twist);
    j.set_buttons(buttons);
    j.set_trigger(trigger);
    return Send(JoystickReading{j, now_});
  }

  Effects Voice(devices::VoiceCommand c, uint64_t sequence) {
    now_ += 10 * kMs;
    devices::VoiceState v;
    v.set_command(c);
    v.mutable_stamp()->set_sequence(sequence);
    return Send(VoiceReading{v, now_});
  }

  video::GrabResponse GrabAt(uint64_t frame_id, double pan_rad) {
    video::GrabResponse g;
    g.set_frame_id(frame_id);
    g.mutable_pose()->add_joints_rad(pan_rad);
    g.mutable_pose()->add_joints_rad(0);
    g.mutable_pose()->add_joints_rad(0);
    g.mutable_pose()->set_from_platform(true);
    return g;
  }

  // Freezes (by keyboard), lets the platform settle and answers the grab at `pan_rad`.
  void FreezeAndGrab(uint64_t frame_id = 41, double pan_rad = 0.0) {
    Command(CommandKind::kFreeze);
    Platform(false);
    const Effects e = Platform(false);
    const auto grabs = All<GrabEffect>(e);
    ASSERT_EQ(grabs.size(), 1u) << Notices(e);
    now_ += 30 * kMs;
    Send(GrabReply{grabs[0].call, GrabAt(frame_id, pan_rad), now_});
    ASSERT_EQ(session_->mode(), Mode::kModelBuilding);
  }

  // Four marks by the trigger, the pointer moved between them.
  void FourMarks() {
    for (int i = 0; i < 4; ++i) {
      Joystick(0, i % 2 ? 1 : -1, i < 2 ? 1 : -1, 0, false);
      Joystick(0, 0, 0, 0, false, 200 * kMs);
      Joystick(0, 0, 0, 0, true);
      Joystick(0, 0, 0, 0, false);
    }
    ASSERT_EQ(session_->marks().size(), 4u);
  }

  // Identifies as a cylinder by voice; the Locate call.
  LocateEffect Identify() {
    Send(VoiceSubscribed{voice_sequence_, now_});
    const Effects e = Voice(devices::VOICE_CYLINDER, ++voice_sequence_);
    const auto calls = All<LocateEffect>(e);
    EXPECT_EQ(calls.size(), 1u) << Notices(e);
    return calls.empty() ? LocateEffect{} : calls[0];
  }

  object::LocateResponse Found(const Eigen::Vector3d& center, double radius = 1.0,
                               double height = 6.0) {
    object::LocateResponse r;
    r.set_found(true);
    r.set_type(object::OBJECT_TYPE_CYLINDER);
    *r.mutable_cylinder()->mutable_center() = ToVec3(center);
    *r.mutable_cylinder()->mutable_axis() = ToVec3(Eigen::Vector3d::UnitZ());
    r.mutable_cylinder()->set_radius(radius);
    r.mutable_cylinder()->set_height(height);
    return r;
  }

  // A model stored at `center` through a whole freeze, marks and identify.
  void BuildModelAt(const Eigen::Vector3d& center) {
    FourMarks();
    const LocateEffect call = Identify();
    now_ += 50 * kMs;
    Send(LocateReply{call.call, Found(center), now_});
    ASSERT_EQ(session_->mode(), Mode::kModelBuilding);
  }

  calibration::StereoCalibration calibration_;
  std::unique_ptr<Session> session_;
  int64_t now_ = 1'000'000'000'000;
  uint64_t viewer_sequence_ = 0, platform_sequence_ = 0, joystick_sequence_ = 0;
  uint64_t voice_sequence_ = 0;
};

// ---- start (2.4) ----

TEST_F(SessionTest, StartPlaysTheIntroductionThenWelcome) {
  const Effects e = Send(AllUp());
  EXPECT_EQ(session_->mode(), Mode::kVerification);
  EXPECT_EQ(States(e), std::vector{devices::VERIFICATION});
  EXPECT_EQ(Sounds(e), std::vector<std::string>{cues::kIntroductionMusic});
  now_ += 1799 * kMs;
  EXPECT_TRUE(Sounds(Send(TickEvent{now_})).empty());
  now_ += 1 * kMs;
  EXPECT_EQ(Sounds(Send(TickEvent{now_})), std::vector<std::string>{cues::kWelcome});
  now_ += 1000 * kMs;
  EXPECT_TRUE(Sounds(Send(TickEvent{now_})).empty());
}

TEST_F(SessionTest, AMissingRequiredPeerStopsTheStartNamingIt) {
  StartEvent start = AllUp();
  start.peers[0].up = false;  // video
  start.peers[0].why = "connection refused";
  start.peers[3].up = false;  // viewer
  const Effects e = Send(start);
  const auto exits = All<ExitEffect>(e);
  ASSERT_EQ(exits.size(), 1u);
  EXPECT_EQ(exits[0].code, 1);
  EXPECT_NE(exits[0].message.find("video (127.0.0.1:7300): connection refused"), std::string::npos)
      << exits[0].message;
  EXPECT_NE(exits[0].message.find("viewer (127.0.0.1:7303)"), std::string::npos);
  EXPECT_EQ(session_->mode(), Mode::kStopped);
  EXPECT_FALSE(Has<SetOperatorStateEffect>(e));
  EXPECT_FALSE(Has<PlaySoundEffect>(e));
}

TEST_F(SessionTest, AMissingOptionalPeerIsNamedAndTheSessionGoesOn) {
  StartEvent start = AllUp();
  start.peers[5].up = false;  // sound
  start.peers[7].up = false;  // ranger
  const Effects e = Send(start);
  EXPECT_EQ(session_->mode(), Mode::kVerification);
  EXPECT_NE(Notices(e).find("sound (127.0.0.1:7305)"), std::string::npos) << Notices(e);
  EXPECT_NE(Notices(e).find("ranger (127.0.0.1:7307)"), std::string::npos);
  // Without a sound server nothing is played, and the session works.
  EXPECT_FALSE(Has<PlaySoundEffect>(e));
  EXPECT_FALSE(Has<ExitEffect>(e));
  FreezeAndGrab();
}

TEST_F(SessionTest, APeerLeftOutOfTheLabFileIsMissing) {
  StartEvent start = AllUp();
  start.peers.erase(start.peers.begin() + 1);  // object
  const auto exits = All<ExitEffect>(Send(start));
  ASSERT_EQ(exits.size(), 1u);
  EXPECT_NE(exits[0].message.find("object: not in the lab file"), std::string::npos);
}

TEST_F(SessionTest, WithWaitTheStartWaitsForTheMissingPeer) {
  SessionOptions options;
  options.wait_for_peers = true;
  Make(options);
  StartEvent start = AllUp();
  start.peers[2].up = false;  // platform
  Effects e = Send(start);
  EXPECT_EQ(session_->mode(), Mode::kStarting);
  EXPECT_FALSE(Has<ExitEffect>(e));
  EXPECT_NE(Notices(e).find("waiting for required peers: platform"), std::string::npos);
  e = Send(PeerUpEvent{Peer::kPlatform, now_});
  EXPECT_EQ(session_->mode(), Mode::kVerification);
  EXPECT_EQ(States(e), std::vector{devices::VERIFICATION});
}

TEST_F(SessionTest, BadOptionsAreRefusedNamingTheSetting) {
  SessionOptions options;
  options.pointer_speed = -1;
  std::string why;
  EXPECT_FALSE(Session::Make(options, testing::ThesisCalibration(), &why));
  EXPECT_NE(why.find("pointer_speed"), std::string::npos) << why;
}

// ---- verification ----

TEST_F(SessionTest, TheViewerDrivesThePlatformThroughTheCalibration) {
  Start();
  const Effects e = Viewer(10.0, 5.0, 2.0);
  const auto set = All<SetOrientationEffect>(e);
  ASSERT_EQ(set.size(), 1u);
  // Pan only, as in the thesis: 10 degrees / 3.684e-3 degrees a tick.
  EXPECT_EQ(set[0].ticks.yaw, std::lround(10.0 / geometry::ThesisPanDegreesPerTick()));
  EXPECT_EQ(set[0].ticks.pitch, 0);
  EXPECT_EQ(set[0].ticks.roll, 0);
}

TEST_F(SessionTest, AllThreeAxesWhenAskedWithTheTiltSignFlipped) {
  SessionOptions options;
  options.all_axes = true;
  Make(options);
  Start();
  const auto set = All<SetOrientationEffect>(Viewer(0.0, 5.0, 0.0));
  ASSERT_EQ(set.size(), 1u);
  // Nose down 5 degrees: the platform tilts down, negative ticks (positive looks up).
  EXPECT_EQ(set[0].ticks.pitch, -std::lround(5.0 / geometry::ThesisTiltDegreesPerTick()));
}

TEST_F(SessionTest, OneOrientationInFlightAndTheNewestWins) {
  Start();
  const auto first = All<SetOrientationEffect>(Viewer(1.0));
  ASSERT_EQ(first.size(), 1u);
  // While it is in flight, readings replace one another; nothing is sent or queued.
  EXPECT_FALSE(Has<SetOrientationEffect>(Viewer(2.0)));
  EXPECT_FALSE(Has<SetOrientationEffect>(Viewer(3.0)));
  EXPECT_FALSE(Has<SetOrientationEffect>(Viewer(4.0)));
  // An answer to another call changes nothing.
  EXPECT_FALSE(Has<SetOrientationEffect>(Send(SetOrientationReply{first[0].call + 100, {}, now_})));
  const auto next = All<SetOrientationEffect>(Send(SetOrientationReply{first[0].call, {}, now_}));
  ASSERT_EQ(next.size(), 1u);
  EXPECT_EQ(next[0].ticks, session_->viewer_to_platform().Ticks({4.0, 0, 0}));
  EXPECT_NE(next[0].call, first[0].call);
  // Its answer leaves nothing pending; the same orientation is not sent again.
  EXPECT_FALSE(Has<SetOrientationEffect>(Send(SetOrientationReply{next[0].call, {}, now_})));
  EXPECT_FALSE(Has<SetOrientationEffect>(Viewer(4.0)));
  EXPECT_TRUE(Has<SetOrientationEffect>(Viewer(4.5)));
}

TEST_F(SessionTest, ARefusedOrientationIsSaidOnceAndTriedAgain) {
  Start();
  const auto first = All<SetOrientationEffect>(Viewer(1.0));
  ASSERT_EQ(first.size(), 1u);
  Effects e =
      Send(SetOrientationReply{first[0].call, CallError{UNAVAILABLE, "not connected"}, now_});
  EXPECT_NE(Notices(e).find("UNAVAILABLE: not connected"), std::string::npos);
  const auto again = All<SetOrientationEffect>(Viewer(1.0));
  ASSERT_EQ(again.size(), 1u);
  e = Send(SetOrientationReply{again[0].call, CallError{UNAVAILABLE, "not connected"}, now_});
  EXPECT_TRUE(Notices(e).empty());
}

TEST_F(SessionTest, APlatformHeldByAnotherClientIsNotTakenUnasked) {
  Start();
  const auto first = All<SetOrientationEffect>(Viewer(1.0));
  ASSERT_EQ(first.size(), 1u);
  EXPECT_FALSE(first[0].take_control);
  const std::string held = "the platform is controlled by igmsctl at 127.0.0.1:40000; ...";
  Effects e = Send(SetOrientationReply{first[0].call, CallError{PERMISSION_DENIED, held}, now_});
  EXPECT_NE(Notices(e).find("does not obey this session: " + held), std::string::npos)
      << Notices(e);
  // Asked again with the next reading, still without taking it, and said once.
  const auto again = All<SetOrientationEffect>(Viewer(1.5));
  ASSERT_EQ(again.size(), 1u);
  EXPECT_FALSE(again[0].take_control);
  e = Send(SetOrientationReply{again[0].call, CallError{PERMISSION_DENIED, held}, now_});
  EXPECT_TRUE(Notices(e).empty());
  // The other let go: obeyed again, and said so.
  const auto obeyed = All<SetOrientationEffect>(Viewer(2.0));
  ASSERT_EQ(obeyed.size(), 1u);
  e = Send(SetOrientationReply{obeyed[0].call, {}, now_});
  EXPECT_NE(Notices(e).find("obeys this session again"), std::string::npos) << Notices(e);
  // Taken by another, then the link lost: the reconnected session does not take it back.
  const auto taken = All<SetOrientationEffect>(Viewer(2.5));
  ASSERT_EQ(taken.size(), 1u);
  Send(SetOrientationReply{taken[0].call, CallError{PERMISSION_DENIED, held}, now_});
  Send(PeerDownEvent{Peer::kPlatform, "connection reset", now_});
  const auto back = All<SetOrientationEffect>(Send(PeerUpEvent{Peer::kPlatform, now_}));
  ASSERT_EQ(back.size(), 1u);
  EXPECT_FALSE(back[0].take_control);
}

TEST_F(SessionTest, TakeControlAtStartAndBackAfterItsOwnConnectionWasLost) {
  SessionOptions options;
  options.take_control = true;
  Make(options);
  Start();
  const auto first = All<SetOrientationEffect>(Viewer(1.0));
  ASSERT_EQ(first.size(), 1u);
  EXPECT_TRUE(first[0].take_control);
  Send(SetOrientationReply{first[0].call, {}, now_});
  const auto next = All<SetOrientationEffect>(Viewer(2.0));
  ASSERT_EQ(next.size(), 1u);
  EXPECT_FALSE(next[0].take_control);  // held now: nothing to take
  Send(SetOrientationReply{next[0].call, {}, now_});
  // Its connection lost while in control: the daemon may still count the dead connection
  // as the holder, so the command after reconnecting takes control back.
  Send(PeerDownEvent{Peer::kPlatform, "connection reset", now_});
  const auto back = All<SetOrientationEffect>(Send(PeerUpEvent{Peer::kPlatform, now_}));
  ASSERT_EQ(back.size(), 1u);
  EXPECT_TRUE(back[0].take_control);
  Send(SetOrientationReply{back[0].call, {}, now_});
  const auto after = All<SetOrientationEffect>(Viewer(3.0));
  ASSERT_EQ(after.size(), 1u);
  EXPECT_FALSE(after[0].take_control);
}

// ---- freeze ----

TEST_F(SessionTest, FreezeByButtonsWaitsForThePlatformToStopThenGrabs) {
  Start();
  const auto sent = All<SetOrientationEffect>(Viewer(10.0));
  ASSERT_EQ(sent.size(), 1u);
  // Buttons 01 held: nothing until 100 ms on the readings' stamps.
  Effects e;
  for (int i = 0; i < 7; ++i) {
    e = Viewer(12.0, 0, 0, false, true);
    ASSERT_FALSE(Has<PlaySoundEffect>(e)) << i;
  }
  e = Viewer(12.0, 0, 0, false, true);  // 7 x 14 = 98 ms after the first reading
  ASSERT_FALSE(Has<PlaySoundEffect>(e));
  e = Viewer(12.0, 0, 0, false, true);  // 112 ms
  EXPECT_EQ(Sounds(e), (std::vector<std::string>{cues::kCameraClick, cues::kFreezing}));
  EXPECT_EQ(States(e), std::vector{devices::MODEL_BUILDING});
  EXPECT_EQ(session_->mode(), Mode::kFreezing);
  // Stop commanding: the reading newer than the one in flight is not sent after it.
  EXPECT_FALSE(Has<GrabEffect>(e));
  EXPECT_FALSE(Has<SetOrientationEffect>(Viewer(20.0)));
  // Not-moving readings while the last orientation is in flight do not count.
  EXPECT_FALSE(Has<GrabEffect>(Platform(false)));
  EXPECT_FALSE(Has<GrabEffect>(Platform(false)));
  e = Send(SetOrientationReply{sent[0].call, {}, now_});
  EXPECT_FALSE(Has<SetOrientationEffect>(e));
  EXPECT_FALSE(Has<GrabEffect>(e));
  // Moving, then still twice in a row: grab.
  EXPECT_FALSE(Has<GrabEffect>(Platform(true)));
  EXPECT_FALSE(Has<GrabEffect>(Platform(false)));
  EXPECT_FALSE(Has<GrabEffect>(Platform(true)));
  EXPECT_FALSE(Has<GrabEffect>(Platform(false)));
  const auto grabs = All<GrabEffect>(Platform(false));
  ASSERT_EQ(grabs.size(), 1u);
  EXPECT_EQ(session_->mode(), Mode::kGrabbing);
  // Readings after the grab leave it alone.
  EXPECT_FALSE(Has<GrabEffect>(Platform(false)));

  // The cameras come from the grab's pose: panned 10 degrees.
  const double pan = 10.0 * M_PI / 180.0;
  e = Send(GrabReply{grabs[0].call, GrabAt(77, pan), now_});
  EXPECT_EQ(session_->mode(), Mode::kModelBuilding);
  EXPECT_FALSE(Has<SetOperatorStateEffect>(e));  // already model building
  ASSERT_TRUE(session_->frozen());
  EXPECT_EQ(session_->frozen()->grab.frame_id(), 77u);
  const geometry::Matrix34 expected = geometry::CameraAtPose(
      calibration_.left.P, *calibration_.platform, std::vector<double>{pan, 0, 0});
  EXPECT_LT((session_->frozen()->left_P - expected).norm(), 1e-9);
  // The pointer starts on the left camera's optical axis at the configured depth (36).
  const geometry::ProjectiveCamera left(expected, calibration_.left.image_size);
  ASSERT_TRUE(session_->pointer());
  EXPECT_NEAR(left.Depth(*session_->pointer()), 36.0, 1e-9);
  EXPECT_NEAR((*session_->pointer() - left.Center()).normalized().dot(left.ViewDirection()), 1.0,
              1e-12);
}

TEST_F(SessionTest, PassingThrough01OnTheWayTo11DoesNotFreeze) {
  Start();
  Effects all;
  for (int i = 0; i < 4; ++i) {  // 01 for 42 ms
    Effects e = Viewer(0.0, 0, 0, false, true);
    all.insert(all.end(), e.begin(), e.end());
  }
  for (int i = 0; i < 20; ++i) {  // then 11 held
    Effects e = Viewer(0.0, 0, 0, true, true);
    all.insert(all.end(), e.begin(), e.end());
  }
  EXPECT_EQ(session_->mode(), Mode::kVerification);
  EXPECT_FALSE(Has<GrabEffect>(all));
  EXPECT_FALSE(Has<PlaySoundEffect>(all));
  // 11 (unfreeze) once held is refused in verification, once.
  EXPECT_EQ(All<NoticeEffect>(all).size(), 1u) << Notices(all);
  EXPECT_NE(Notices(all).find("unfreeze (viewer_buttons) is not valid while verification"),
            std::string::npos);
}

TEST_F(SessionTest, AStillPlatformThatNeverSaysSoIsGrabbedAfterTheTimeout) {
  Start();
  Command(CommandKind::kFreeze);
  now_ += 2999 * kMs;
  EXPECT_FALSE(Has<GrabEffect>(Send(TickEvent{now_})));
  now_ += 1 * kMs;
  const Effects e = Send(TickEvent{now_});
  EXPECT_EQ(All<GrabEffect>(e).size(), 1u);
  EXPECT_NE(Notices(e).find("grabbing anyway"), std::string::npos);
}

TEST_F(SessionTest, WithThePlatformDaemonDownFreezeGrabsAtOnce) {
  Start();
  Send(PeerDownEvent{Peer::kPlatform, "connection refused", now_});
  const Effects e = Command(CommandKind::kFreeze);
  EXPECT_EQ(All<GrabEffect>(e).size(), 1u);
  EXPECT_NE(Notices(e).find("the platform is not connected"), std::string::npos);
}

TEST_F(SessionTest, AFailedGrabGoesBackToVerification) {
  Start();
  Viewer(5.0);
  Send(SetOrientationReply{1, {}, now_});
  Command(CommandKind::kFreeze);
  Platform(false);
  const auto grabs = All<GrabEffect>(Platform(false));
  ASSERT_EQ(grabs.size(), 1u);
  const Effects e = Send(GrabReply{grabs[0].call, CallError{UNAVAILABLE, "no camera"}, now_});
  EXPECT_EQ(session_->mode(), Mode::kVerification);
  EXPECT_EQ(States(e), std::vector{devices::VERIFICATION});
  EXPECT_NE(Notices(e).find("UNAVAILABLE: no camera"), std::string::npos);
  EXPECT_FALSE(session_->frozen());
  EXPECT_TRUE(Has<SetOrientationEffect>(Viewer(6.0)));
}

// ---- pointer (table 2.2) and range ----

TEST_F(SessionTest, TheStickMovesThePointerIntegratedOverTheStamps) {
  Start();
  FreezeAndGrab();
  const CameraFrame f = session_->frozen()->left_frame;
  const Eigen::Vector3d start = *session_->pointer();
  // Full forward for 0.5 s in readings 20 ms apart, then irregular gaps of 7 and 33 ms.
  Joystick(1.0, 0, 0, 0, false);
  for (int i = 0; i < 25; ++i) Joystick(1.0, 0, 0, 0, false);
  Joystick(1.0, 0, 0, 0, false, 7 * kMs);
  Joystick(0.0, 0, 0, 0, false, 33 * kMs);  // released: the 33 ms still moved at full speed
  Joystick(0.0, 0, 0, 0, false);
  // 6 in/s for 0.5 + 0.007 + 0.033 s = 3.24 in along the optical axis.
  Eigen::Vector3d moved = *session_->pointer() - start;
  EXPECT_NEAR(moved.dot(f.forward), 6.0 * 0.54, 1e-9);
  EXPECT_NEAR(moved.dot(f.right), 0.0, 1e-9);
  // Half right and full twist (up) for 0.2 s.
  const Eigen::Vector3d before = *session_->pointer();
  Joystick(0.0, 0.5, 1.0, 0, false);
  for (int i = 0; i < 10; ++i) Joystick(0.0, 0.5, 1.0, 0, false);
  Joystick(0, 0, 0, 0, false);
  moved = *session_->pointer() - before;
  EXPECT_NEAR(moved.dot(f.right), 6.0 * 0.5 * 0.22, 1e-9);
  EXPECT_NEAR(moved.dot(f.up()), 6.0 * 0.22, 1e-9);
  EXPECT_NEAR(moved.dot(f.forward), 0.0, 1e-9);
  // Up in the image is up in the world for the thesis's level cameras.
  EXPECT_GT(f.up().z(), 0.99);
}

TEST_F(SessionTest, ASilentStickDoesNotFlingThePointer) {
  Start();
  FreezeAndGrab();
  const Eigen::Vector3d start = *session_->pointer();
  Joystick(1.0, 0, 0, 0, false);
  Joystick(1.0, 0, 0, 0, false, 5000 * kMs);  // five seconds of silence count 100 ms
  EXPECT_NEAR((*session_->pointer() - start).norm(), 6.0 * 0.1, 1e-9);
}

TEST_F(SessionTest, TheStickDoesNothingInVerification) {
  Start();
  Joystick(1.0, 1.0, 1.0, 0, false);
  Joystick(1.0, 1.0, 1.0, 0, false);
  EXPECT_FALSE(session_->pointer());
}

TEST_F(SessionTest, RangeJumpsThePointerAlongTheBeamAtTheGrabPose) {
  Start();
  const double pan = -15.0 * M_PI / 180.0;
  FreezeAndGrab(41, pan);
  Effects e = Command(CommandKind::kRange, CommandSource::kVoice);
  EXPECT_EQ(Sounds(e), std::vector<std::string>{cues::kRicochet});
  const auto calls = All<RangeEffect>(e);
  ASSERT_EQ(calls.size(), 1u);
  // One measurement at a time.
  EXPECT_FALSE(Has<RangeEffect>(Command(CommandKind::kRange)));
  devices::RangerState r;
  r.set_valid(true);
  r.set_range_in(40.0);
  e = Send(RangeReply{calls[0].call, r, now_});
  const Beam beam = BeamAt(calibration_, std::vector<double>{pan, 0, 0});
  EXPECT_LT((*session_->pointer() - (beam.origin + 40.0 * beam.axis)).norm(), 1e-9);
  // The beam turned with the platform: its heading moved by the pan.
  const Beam zero = BeamAt(calibration_, std::vector<double>{0, 0, 0});
  EXPECT_NEAR(std::atan2(beam.axis.y(), beam.axis.x()) - std::atan2(zero.axis.y(), zero.axis.x()),
              pan, 1e-9);
  EXPECT_DOUBLE_EQ(session_->range(), 40.0);
  // The range goes into the locate request.
  FourMarks();
  EXPECT_DOUBLE_EQ(Identify().request.range(), 40.0);
}

TEST_F(SessionTest, RangeInMetresCalibrations) {
  SessionOptions options;
  options.world_units_per_inch = 0.0254;
  Make(options);
  Start();
  FreezeAndGrab();
  const auto calls = All<RangeEffect>(Command(CommandKind::kRange));
  ASSERT_EQ(calls.size(), 1u);
  devices::RangerState r;
  r.set_valid(true);
  r.set_range_in(100.0);
  Send(RangeReply{calls[0].call, r, now_});
  EXPECT_DOUBLE_EQ(session_->range(), 2.54);
}

TEST_F(SessionTest, NoEchoIsSaidAndThePointerStays) {
  Start();
  FreezeAndGrab();
  const Eigen::Vector3d before = *session_->pointer();
  const auto calls = All<RangeEffect>(Command(CommandKind::kRange));
  ASSERT_EQ(calls.size(), 1u);
  devices::RangerState r;
  r.set_valid(false);
  const Effects e = Send(RangeReply{calls[0].call, r, now_});
  EXPECT_EQ(Sounds(e), std::vector<std::string>{cues::kNoEcho});
  EXPECT_NE(Notices(e).find("no echo"), std::string::npos);
  EXPECT_EQ(*session_->pointer(), before);
  EXPECT_EQ(session_->range(), 0.0);
}

TEST_F(SessionTest, RangeWithoutARangerOrInVerification) {
  Start();
  // Table 2.1's 10 in verification is not valid.
  Effects e = Command(CommandKind::kRange, CommandSource::kViewerButtons);
  EXPECT_FALSE(Has<RangeEffect>(e));
  EXPECT_NE(Notices(e).find("not valid while verification"), std::string::npos);
  FreezeAndGrab();
  Send(PeerDownEvent{Peer::kRanger, "connection reset", now_});
  e = Command(CommandKind::kRange);
  EXPECT_FALSE(Has<RangeEffect>(e));
  EXPECT_NE(Notices(e).find("ranger (127.0.0.1:7307) is not connected"), std::string::npos);
}

TEST_F(SessionTest, ARangeAnsweredAfterUnfreezingIsIgnored) {
  Start();
  FreezeAndGrab();
  const auto calls = All<RangeEffect>(Command(CommandKind::kRange));
  ASSERT_EQ(calls.size(), 1u);
  Command(CommandKind::kUnfreeze);
  devices::RangerState r;
  r.set_valid(true);
  r.set_range_in(40.0);
  EXPECT_TRUE(Send(RangeReply{calls[0].call, r, now_}).empty());
  EXPECT_FALSE(session_->pointer());
}

// ---- marks ----

TEST_F(SessionTest, FourMarksAskForTheObjectType) {
  Start();
  FreezeAndGrab();
  Effects e;
  for (int i = 0; i < 3; ++i) {
    Joystick(0, 0, 0, 0, false);
    e = Joystick(0, 0, 0, 0, true);
    EXPECT_EQ(Sounds(e), std::vector<std::string>{cues::kWoodblock});
    EXPECT_FALSE(Has<SetOperatorStateEffect>(e));
  }
  Joystick(0, 0, 0, 0, false);
  e = Send(CommandEvent{{CommandKind::kMark, CommandSource::kVoice, now_}, now_});
  EXPECT_EQ(Sounds(e), (std::vector<std::string>{cues::kWoodblock, cues::kBoxOrCylinder}));
  EXPECT_EQ(All<PlaySoundEffect>(e)[1].priority, sound::PRIORITY_HIGH);
  EXPECT_EQ(States(e), std::vector{devices::AWAITING_OBJECT_TYPE});
  EXPECT_EQ(session_->mode(), Mode::kAwaitingType);
  // A fifth mark is not valid.
  e = Command(CommandKind::kMark);
  EXPECT_TRUE(Sounds(e).empty());
  EXPECT_EQ(session_->marks().size(), 4u);
}

TEST_F(SessionTest, UnmarkRemovesTheLastMarkAndReturnsToModelBuilding) {
  Start();
  FreezeAndGrab();
  FourMarks();
  const Eigen::Vector3d third = session_->marks()[2];
  // FlyBox button 1.
  Joystick(0, 0, 0, 0, false);
  const Effects e = Joystick(0, 0, 0, 0x1, false);
  EXPECT_EQ(Sounds(e), std::vector<std::string>{cues::kUnmark});
  EXPECT_EQ(States(e), std::vector{devices::MODEL_BUILDING});
  ASSERT_EQ(session_->marks().size(), 3u);
  EXPECT_EQ(session_->marks().back(), third);
  EXPECT_EQ(session_->mode(), Mode::kModelBuilding);
}

TEST_F(SessionTest, RemovePointsClearsEveryMark) {
  Start();
  FreezeAndGrab();
  FourMarks();
  Send(VoiceSubscribed{0, now_});
  const Effects e = Voice(devices::VOICE_REMOVE_POINTS, 1);
  EXPECT_EQ(Sounds(e), std::vector<std::string>{cues::kRemovingPoints});
  EXPECT_EQ(States(e), std::vector{devices::MODEL_BUILDING});
  EXPECT_TRUE(session_->marks().empty());
  // Nothing left to unmark.
  EXPECT_NE(Notices(Command(CommandKind::kUnmark)).find("no mark"), std::string::npos);
}

// ---- identify ----

TEST_F(SessionTest, IdentifyLocatesAndStoresTheModel) {
  Start();
  FreezeAndGrab(41);
  FourMarks();
  const std::vector<Eigen::Vector3d> marks = session_->marks();
  Send(VoiceSubscribed{0, now_});
  Effects e = Voice(devices::VOICE_CYLINDER, 1);
  EXPECT_EQ(Sounds(e),
            (std::vector<std::string>{cues::kModelingAsCylinder, cues::kLocatingObject}));
  // While locating the grammar is model building's (wireframe and solid are heard).
  EXPECT_EQ(States(e), std::vector{devices::MODEL_BUILDING});
  const auto calls = All<LocateEffect>(e);
  ASSERT_EQ(calls.size(), 1u);
  const object::LocateRequest& req = calls[0].request;
  EXPECT_EQ(req.type(), object::OBJECT_TYPE_CYLINDER);
  EXPECT_EQ(req.frame_id(), 41u);
  EXPECT_EQ(req.range(), 0.0);
  ASSERT_EQ(req.marks_size(), 4);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(ToEigen(req.marks(i)), marks[i]);
  EXPECT_EQ(session_->mode(), Mode::kLocating);
  // While locating, only the display changes.
  EXPECT_FALSE(Has<PlaySoundEffect>(Command(CommandKind::kUnfreeze)));
  EXPECT_EQ(session_->mode(), Mode::kLocating);
  EXPECT_TRUE(Has<DisplayEffect>(Command(CommandKind::kWireframe)));

  e = Send(LocateReply{calls[0].call, Found({1, 2, 3}), now_});
  const auto stored = All<StoreModelEffect>(e);
  ASSERT_EQ(stored.size(), 1u);
  EXPECT_EQ(stored[0].model.id, 1u);
  EXPECT_EQ(stored[0].model.type, object::OBJECT_TYPE_CYLINDER);
  EXPECT_EQ(stored[0].provenance.grab.frame_id(), 41u);
  EXPECT_EQ(stored[0].provenance.request.marks_size(), 4);
  EXPECT_TRUE(stored[0].provenance.response.found());
  EXPECT_EQ(Sounds(e), std::vector<std::string>{cues::kBellTree});
  EXPECT_TRUE(States(e).empty());  // still model building
  EXPECT_TRUE(session_->marks().empty());
  EXPECT_EQ(session_->models().size(), 1u);
  EXPECT_EQ(session_->mode(), Mode::kModelBuilding);
  // The same answer again is not stored twice.
  EXPECT_TRUE(Send(LocateReply{calls[0].call, Found({1, 2, 3}), now_}).empty());
}

TEST_F(SessionTest, PleaseWaitAfterTwoSecondsOfLocatingOnce) {
  Start();
  FreezeAndGrab();
  FourMarks();
  const LocateEffect call = Identify();
  now_ += 1990 * kMs;
  EXPECT_TRUE(Sounds(Send(TickEvent{now_})).empty());
  now_ += 10 * kMs;
  EXPECT_EQ(Sounds(Send(TickEvent{now_})), std::vector<std::string>{cues::kPleaseWait});
  now_ += 3000 * kMs;
  EXPECT_TRUE(Sounds(Send(TickEvent{now_})).empty());
  Send(LocateReply{call.call, Found({0, 0, 0}), now_});
  // A quick locate never says it.
  FourMarks();
  const LocateEffect quick = Identify();
  now_ += 300 * kMs;
  Send(TickEvent{now_});
  Send(LocateReply{quick.call, Found({5, 0, 0}), now_});
  now_ += 5000 * kMs;
  EXPECT_TRUE(Sounds(Send(TickEvent{now_})).empty());
}

TEST_F(SessionTest, NotFoundSpeaksTheReasonAndKeepsTheDetail) {
  Start();
  FreezeAndGrab();
  FourMarks();
  const LocateEffect call = Identify();
  object::LocateResponse r;
  r.set_found(false);
  r.set_reason(object::FAILURE_NO_EDGE_NEAR_MARKS);
  r.set_detail("no edge stronger than 6.0 grey levels per pixel inside the marks");
  const Effects e = Send(LocateReply{call.call, r, now_});
  const auto spoken = All<SpeakFailureEffect>(e);
  ASSERT_EQ(spoken.size(), 1u);
  EXPECT_EQ(spoken[0].reason, object::FAILURE_NO_EDGE_NEAR_MARKS);
  EXPECT_EQ(session_->failure_detail(), r.detail());
  EXPECT_NE(Notices(e).find(r.detail()), std::string::npos);
  EXPECT_FALSE(Has<StoreModelEffect>(e));
  // Back to awaiting the type, said again (the voice daemon predicted model building).
  EXPECT_EQ(States(e), std::vector{devices::AWAITING_OBJECT_TYPE});
  EXPECT_EQ(session_->mode(), Mode::kAwaitingType);
  EXPECT_EQ(session_->marks().size(), 4u);
  // The other type may be tried on the same marks.
  EXPECT_EQ(All<LocateEffect>(Command(CommandKind::kIdentifyBox))[0].request.type(),
            object::OBJECT_TYPE_BOX);
}

TEST_F(SessionTest, AFrameNoLongerHeldIsGrabbedAgainAndSentOnce) {
  Start();
  FreezeAndGrab(41);
  FourMarks();
  const LocateEffect first = Identify();
  Effects e = Send(LocateReply{first.call, CallError{NOT_FOUND, "frame 41 was evicted"}, now_});
  const auto grabs = All<GrabEffect>(e);
  ASSERT_EQ(grabs.size(), 1u);
  EXPECT_FALSE(Has<LocateEffect>(e));
  EXPECT_FALSE(Has<SetOrientationEffect>(e));  // the platform stays where it is
  EXPECT_EQ(session_->mode(), Mode::kLocating);
  e = Send(GrabReply{grabs[0].call, GrabAt(42, 0.0), now_});
  const auto second = All<LocateEffect>(e);
  ASSERT_EQ(second.size(), 1u);
  EXPECT_EQ(second[0].request.frame_id(), 42u);
  EXPECT_EQ(second[0].request.marks_size(), 4);
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(ToEigen(second[0].request.marks(i)), ToEigen(first.request.marks(i)));
  // Not held again: said, and no third try.
  e = Send(LocateReply{second[0].call, CallError{NOT_FOUND, "frame 42 was evicted"}, now_});
  EXPECT_FALSE(Has<GrabEffect>(e));
  EXPECT_FALSE(Has<LocateEffect>(e));
  EXPECT_NE(Notices(e).find("NOT_FOUND: frame 42 was evicted"), std::string::npos);
  EXPECT_EQ(session_->mode(), Mode::kAwaitingType);
}

TEST_F(SessionTest, AFailedRegrabEndsTheLocate) {
  Start();
  FreezeAndGrab(41);
  FourMarks();
  const LocateEffect first = Identify();
  const auto grabs =
      All<GrabEffect>(Send(LocateReply{first.call, CallError{NOT_FOUND, "evicted"}, now_}));
  ASSERT_EQ(grabs.size(), 1u);
  const Effects e = Send(GrabReply{grabs[0].call, CallError{TIMEOUT, "camera"}, now_});
  EXPECT_FALSE(Has<LocateEffect>(e));
  EXPECT_EQ(session_->mode(), Mode::kAwaitingType);
  EXPECT_EQ(States(e), std::vector{devices::AWAITING_OBJECT_TYPE});
}

TEST_F(SessionTest, OtherLocateErrorsAreSaidAndTheMarksKept) {
  Start();
  FreezeAndGrab();
  FourMarks();
  const LocateEffect call = Identify();
  const Effects e = Send(
      LocateReply{call.call, CallError{UNAVAILABLE, "video server: connection refused"}, now_});
  EXPECT_FALSE(Has<GrabEffect>(e));
  EXPECT_NE(Notices(e).find("UNAVAILABLE: video server: connection refused"), std::string::npos);
  EXPECT_EQ(session_->mode(), Mode::kAwaitingType);
  EXPECT_EQ(session_->marks().size(), 4u);
}

TEST_F(SessionTest, IdentifyWithTheObjectServerDownIsRefused) {
  Start();
  FreezeAndGrab();
  FourMarks();
  Send(PeerDownEvent{Peer::kObject, "connection reset", now_});
  const Effects e = Command(CommandKind::kIdentifyBox);
  EXPECT_FALSE(Has<LocateEffect>(e));
  EXPECT_NE(Notices(e).find("object (127.0.0.1:7301) is not connected"), std::string::npos);
  EXPECT_EQ(session_->mode(), Mode::kAwaitingType);
}

// ---- unfreeze ----

TEST_F(SessionTest, UnfreezeSlavesThePlatformToTheViewerAgain) {
  Start();
  Viewer(3.0);
  Send(SetOrientationReply{1, {}, now_});
  FreezeAndGrab();
  FourMarks();
  // The head turned while frozen: nothing commanded.
  EXPECT_FALSE(Has<SetOrientationEffect>(Viewer(8.0)));
  // Buttons 11 held.
  Effects e;
  for (int i = 0; i < 9 && !Has<PlaySoundEffect>(e); ++i) e = Viewer(8.0, 0, 0, true, true);
  EXPECT_EQ(Sounds(e), std::vector<std::string>{cues::kUnfreezing});
  EXPECT_EQ(States(e), std::vector{devices::VERIFICATION});
  const auto set = All<SetOrientationEffect>(e);
  ASSERT_EQ(set.size(), 1u);
  EXPECT_EQ(set[0].ticks, session_->viewer_to_platform().Ticks({8.0, 0, 0}));
  EXPECT_EQ(session_->mode(), Mode::kVerification);
  EXPECT_TRUE(session_->marks().empty());
  EXPECT_FALSE(session_->pointer());
  EXPECT_FALSE(session_->frozen());
}

TEST_F(SessionTest, UnfreezeWhileGrabbingIgnoresTheLateGrab) {
  Start();
  Command(CommandKind::kFreeze);
  Platform(false);
  const auto grabs = All<GrabEffect>(Platform(false));
  ASSERT_EQ(grabs.size(), 1u);
  Command(CommandKind::kUnfreeze, CommandSource::kVoice);
  EXPECT_TRUE(Send(GrabReply{grabs[0].call, GrabAt(9, 0), now_}).empty());
  EXPECT_EQ(session_->mode(), Mode::kVerification);
  EXPECT_FALSE(session_->frozen());
}

// ---- voice ----

TEST_F(SessionTest, VoiceActsOnlyWhenNewAndValid) {
  Start();
  // Before subscribing, and the newest command sent on subscribing, do nothing.
  EXPECT_TRUE(Voice(devices::VOICE_FREEZE, 7).empty());
  Send(VoiceSubscribed{7, now_});
  EXPECT_TRUE(Voice(devices::VOICE_FREEZE, 7).empty());
  EXPECT_EQ(session_->mode(), Mode::kVerification);
  // Not valid in verification: refused, said on the display only.
  Effects e = Voice(devices::VOICE_MARK, 8);
  EXPECT_FALSE(Has<PlaySoundEffect>(e));
  EXPECT_NE(Notices(e).find("mark (voice) is not valid while verification"), std::string::npos);
  e = Voice(devices::VOICE_FREEZE, 9);
  EXPECT_EQ(session_->mode(), Mode::kFreezing);
  // The same event delivered twice does not act twice.
  EXPECT_TRUE(Voice(devices::VOICE_FREEZE, 9).empty());
}

TEST_F(SessionTest, TheFlyBoxButtonsFollowTable22) {
  Start();
  FreezeAndGrab();
  Joystick(0, 0, 0, 0, false);
  // Button 2: wireframe, and again solid.
  Effects e = Joystick(0, 0, 0, 0x2, false);
  ASSERT_EQ(All<DisplayEffect>(e).size(), 1u);
  EXPECT_TRUE(All<DisplayEffect>(e)[0].wireframe);
  Joystick(0, 0, 0, 0, false);
  e = Joystick(0, 0, 0, 0x2, false);
  EXPECT_FALSE(All<DisplayEffect>(e)[0].wireframe);
  // Voice wireframe and solid set it; saying it twice changes nothing.
  EXPECT_TRUE(All<DisplayEffect>(Command(CommandKind::kWireframe))[0].wireframe);
  EXPECT_FALSE(Has<DisplayEffect>(Command(CommandKind::kWireframe)));
  EXPECT_FALSE(All<DisplayEffect>(Command(CommandKind::kSolid))[0].wireframe);
}

// ---- remove model and undo ----

TEST_F(SessionTest, RemoveModelInsideAndLastAdded) {
  Start();
  FreezeAndGrab();
  BuildModelAt({0, 0, -500});  // model 1, far below the table
  // Model 2 is stored around wherever the pointer now is.
  BuildModelAt(*session_->pointer() + Eigen::Vector3d(0, 0, 100));  // model 2, far above
  const Eigen::Vector3d p = *session_->pointer();
  // A third model around the pointer, then a fourth far away: remove takes the third.
  BuildModelAt(p);
  BuildModelAt(p + Eigen::Vector3d(0, 0, 300));
  auto removed = All<RemoveModelEffect>(Command(CommandKind::kRemoveModel));
  ASSERT_EQ(removed.size(), 1u);
  EXPECT_EQ(removed[0].id, 3u);
  EXPECT_FALSE(removed[0].undo);
  // In verification there is no pointer: the last added still there (4).
  Command(CommandKind::kUnfreeze);
  removed = All<RemoveModelEffect>(Command(CommandKind::kRemoveModel, CommandSource::kVoice));
  ASSERT_EQ(removed.size(), 1u);
  EXPECT_EQ(removed[0].id, 4u);
  removed = All<RemoveModelEffect>(Command(CommandKind::kRemoveModel));
  ASSERT_EQ(removed.size(), 1u);
  EXPECT_EQ(removed[0].id, 2u);
}

TEST_F(SessionTest, NoModelToRemove) {
  Start();
  const Effects e = Command(CommandKind::kRemoveModel);
  EXPECT_FALSE(Has<RemoveModelEffect>(e));
  EXPECT_FALSE(Has<PlaySoundEffect>(e));
  EXPECT_NE(Notices(e).find("no model to remove"), std::string::npos);
}

TEST_F(SessionTest, UndoTheLastMark) {
  Start();
  FreezeAndGrab();
  FourMarks();
  Effects e = Command(CommandKind::kUndo);
  EXPECT_EQ(session_->marks().size(), 3u);
  EXPECT_EQ(Sounds(e), std::vector<std::string>{cues::kUnmark});
  EXPECT_EQ(States(e), std::vector{devices::MODEL_BUILDING});
  Command(CommandKind::kUndo);
  Command(CommandKind::kUndo);
  Command(CommandKind::kUndo);
  EXPECT_TRUE(session_->marks().empty());
  EXPECT_NE(Notices(Command(CommandKind::kUndo)).find("nothing to undo"), std::string::npos);
}

TEST_F(SessionTest, UndoTheModelAddedAndTheModelRemoved) {
  Start();
  FreezeAndGrab();
  BuildModelAt({0, 0, -500});
  BuildModelAt({0, 0, -700});
  // Undo removes the last model added, with its cue, as a mark of removal.
  Effects e = Command(CommandKind::kUndo);
  auto removed = All<RemoveModelEffect>(e);
  ASSERT_EQ(removed.size(), 1u);
  EXPECT_EQ(removed[0].id, 2u);
  EXPECT_TRUE(session_->models()[1].removed);
  // Remove model 1, then undo brings it back.
  removed = All<RemoveModelEffect>(Command(CommandKind::kRemoveModel));
  ASSERT_EQ(removed.size(), 1u);
  EXPECT_EQ(removed[0].id, 1u);
  e = Command(CommandKind::kUndo);
  const auto restored = All<RestoreModelEffect>(e);
  ASSERT_EQ(restored.size(), 1u);
  EXPECT_EQ(restored[0].id, 1u);
  EXPECT_FALSE(session_->models()[0].removed);
  // Marks placed since a model was added are undone first, then the model.
  Joystick(0, 0, 0, 0, false);
  Joystick(0, 0, 0, 0, true);
  EXPECT_FALSE(Has<RemoveModelEffect>(Command(CommandKind::kUndo)));
  EXPECT_TRUE(session_->marks().empty());
  removed = All<RemoveModelEffect>(Command(CommandKind::kUndo));
  ASSERT_EQ(removed.size(), 1u);
  EXPECT_EQ(removed[0].id, 1u);
  EXPECT_TRUE(removed[0].undo);  // the database records it as the addition undone
}

TEST_F(SessionTest, UnmarkedMarksAreNotUndoneAgain) {
  Start();
  FreezeAndGrab();
  BuildModelAt({0, 0, -500});
  Joystick(0, 0, 0, 0, false);
  Joystick(0, 0, 0, 0, true);
  Command(CommandKind::kUnmark);
  // The undo reaches past the unmarked mark to the model.
  EXPECT_EQ(All<RemoveModelEffect>(Command(CommandKind::kUndo)).size(), 1u);
}

TEST_F(SessionTest, ModelsOfAContinuedSessionKeepTheirIds) {
  Start();
  SessionModel old;
  old.id = 17;
  old.type = object::OBJECT_TYPE_BOX;
  Send(ModelsLoaded{{old}, now_});
  FreezeAndGrab();
  BuildModelAt({0, 0, -500});
  EXPECT_EQ(session_->models().back().id, 18u);
}

// ---- health ----

TEST_F(SessionTest, ALostSoundServerNeverStopsTheSession) {
  Start();
  Effects e = Send(PeerDownEvent{Peer::kSound, "connection reset", now_});
  EXPECT_FALSE(Has<PlaySoundEffect>(e));  // nobody to play it
  EXPECT_NE(Notices(e).find("lost sound (127.0.0.1:7305): connection reset"), std::string::npos);
  FreezeAndGrab();
  FourMarks();
  const LocateEffect call = Identify();
  e = Send(LocateReply{call.call, Found({0, 0, 0}), now_});
  EXPECT_TRUE(Has<StoreModelEffect>(e));
  EXPECT_FALSE(Has<PlaySoundEffect>(e));
  e = Send(PeerUpEvent{Peer::kSound, now_});
  EXPECT_EQ(Sounds(e), std::vector<std::string>{cues::kServerBack});
}

TEST_F(SessionTest, AServerLostAndBack) {
  Start();
  Effects e = Send(PeerDownEvent{Peer::kVideo, "connection refused", now_});
  EXPECT_EQ(Sounds(e), std::vector<std::string>{cues::kServerLost});
  EXPECT_NE(Notices(e).find("lost video (127.0.0.1:7300): connection refused"), std::string::npos);
  EXPECT_TRUE(Send(PeerDownEvent{Peer::kVideo, "again", now_}).empty());
  e = Send(PeerUpEvent{Peer::kVideo, now_});
  EXPECT_EQ(Sounds(e), std::vector<std::string>{cues::kServerBack});
  EXPECT_EQ(session_->mode(), Mode::kVerification);
}

TEST_F(SessionTest, ADeviceLostAndBack) {
  Start();
  Effects e = Send(DeviceLinkEvent{Peer::kJoystick, devices::CONNECTED, "", now_});
  EXPECT_TRUE(e.empty());
  e = Send(DeviceLinkEvent{Peer::kJoystick, devices::STALE, "silent 500 ms", now_});
  EXPECT_EQ(Sounds(e), std::vector<std::string>{cues::kDeviceLost});
  EXPECT_NE(Notices(e).find("joystick device STALE: silent 500 ms"), std::string::npos);
  EXPECT_TRUE(Send(DeviceLinkEvent{Peer::kJoystick, devices::REOPENING, "", now_}).empty());
  e = Send(DeviceLinkEvent{Peer::kJoystick, devices::CONNECTED, "", now_});
  EXPECT_EQ(Sounds(e), std::vector<std::string>{cues::kDeviceBack});
  // A replaying daemon is as good as a connected one.
  EXPECT_TRUE(Send(DeviceLinkEvent{Peer::kJoystick, devices::REPLAYING, "", now_}).empty());
}

TEST_F(SessionTest, ARestartedPlatformDaemonIsPutBackWhileFrozen) {
  Start();
  const double pan = 12.0 * M_PI / 180.0;
  FreezeAndGrab(41, pan);
  // The daemon restarted: its readings count from 1 again, from a new zero.
  platform_sequence_ = 0;
  const Effects e = Platform(false);
  const auto set = All<SetOrientationEffect>(e);
  ASSERT_EQ(set.size(), 1u);
  EXPECT_EQ(set[0].ticks.yaw, std::lround(pan / calibration_.platform->joints[0].radians_per_tick));
  EXPECT_NE(Notices(e).find("putting the platform back"), std::string::npos);
  EXPECT_EQ(session_->mode(), Mode::kModelBuilding);
}

TEST_F(SessionTest, APlatformBackInVerificationIsPutWhereTheSessionHadIt) {
  Start();
  const auto first = All<SetOrientationEffect>(Viewer(20.0));
  ASSERT_EQ(first.size(), 1u);
  Send(SetOrientationReply{first[0].call, {}, now_});
  Send(PeerDownEvent{Peer::kPlatform, "connection reset", now_});
  EXPECT_FALSE(Has<SetOrientationEffect>(Viewer(20.0)));  // nobody to command
  const Effects e = Send(PeerUpEvent{Peer::kPlatform, now_});
  const auto set = All<SetOrientationEffect>(e);
  ASSERT_EQ(set.size(), 1u);  // sent again though the session had sent the same before
  EXPECT_EQ(set[0].ticks, first[0].ticks);
  EXPECT_NE(Notices(e).find("putting the platform back"), std::string::npos);
}

TEST_F(SessionTest, ARestartedViewerKeepsThePlatformWhereItWas) {
  Start();
  viewer_sequence_ = 500;
  const auto first = All<SetOrientationEffect>(Viewer(20.0));
  ASSERT_EQ(first.size(), 1u);
  Send(SetOrientationReply{first[0].call, {}, now_});
  // The viewer daemon restarted: a new zero where the head is (it reads 0 there).
  viewer_sequence_ = 0;
  Effects e = Viewer(0.0);
  EXPECT_FALSE(Has<SetOrientationEffect>(e));  // the platform stays at 20 degrees
  EXPECT_NE(Notices(e).find("new zero"), std::string::npos);
  // Turning the head 5 degrees more turns the platform to 25.
  const auto set = All<SetOrientationEffect>(Viewer(5.0));
  ASSERT_EQ(set.size(), 1u);
  EXPECT_EQ(set[0].ticks, session_->viewer_to_platform().Ticks({25.0, 0, 0}));
}

TEST_F(SessionTest, ABackVoiceDaemonIsToldTheState) {
  Start();
  FreezeAndGrab();
  Send(PeerDownEvent{Peer::kVoice, "connection reset", now_});
  // Nobody to tell while it is away.
  Effects e = Command(CommandKind::kUnfreeze);
  EXPECT_FALSE(Has<SetOperatorStateEffect>(e));
  Command(CommandKind::kFreeze);
  e = Send(PeerUpEvent{Peer::kVoice, now_});
  EXPECT_EQ(States(e), std::vector{devices::MODEL_BUILDING});
}

TEST(SessionHelpers, FailureMessagesAreFoundByTheReasonsEnumName) {
  sound::ListBankResponse bank;
  auto* a = bank.add_sounds();
  a->set_key("not_found_degenerate_marks");
  a->set_reason("FAILURE_MARKS_DEGENERATE");
  auto* b = bank.add_sounds();
  b->set_key("welcome");
  EXPECT_EQ(FailureMessageKey(bank, object::FAILURE_MARKS_DEGENERATE),
            "not_found_degenerate_marks");
  EXPECT_EQ(FailureMessageKey(bank, object::FAILURE_FIT_FAILED), "");
}

TEST(SessionHelpers, ValidCommandsFollowTheVoiceGrammars) {
  // docs/voice.md's words per state are valid in the session's matching modes.
  using C = CommandKind;
  for (C c : {C::kFreeze, C::kWireframe, C::kSolid, C::kRemoveModel})
    EXPECT_TRUE(IsValid(Mode::kVerification, c)) << CommandName(c);
  for (C c : {C::kUnfreeze, C::kRange, C::kMark, C::kUnmark, C::kRemovePoints, C::kWireframe,
              C::kSolid, C::kRemoveModel})
    EXPECT_TRUE(IsValid(Mode::kModelBuilding, c)) << CommandName(c);
  for (C c : {C::kIdentifyBox, C::kIdentifyCylinder, C::kUnmark, C::kRemovePoints, C::kUnfreeze})
    EXPECT_TRUE(IsValid(Mode::kAwaitingType, c)) << CommandName(c);
  for (C c : {C::kUnfreeze, C::kRange, C::kMark, C::kIdentifyBox})
    EXPECT_FALSE(IsValid(Mode::kVerification, c)) << CommandName(c);
  for (C c : {C::kFreeze, C::kIdentifyBox}) EXPECT_FALSE(IsValid(Mode::kModelBuilding, c));
  for (C c : {C::kFreeze, C::kMark, C::kRange}) EXPECT_FALSE(IsValid(Mode::kAwaitingType, c));
  EXPECT_FALSE(IsValid(Mode::kStarting, C::kFreeze));
  EXPECT_EQ(OperatorStateOf(Mode::kLocating), devices::MODEL_BUILDING);
}

}  // namespace
}  // namespace igms::control
