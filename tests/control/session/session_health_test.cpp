// Servers and device daemons lost and back while a session runs.
#include "tests/control/session/session_fixture.h"

namespace igms::control {
namespace {

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

}  // namespace
}  // namespace igms::control
