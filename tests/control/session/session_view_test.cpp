// Verification, freeze and unfreeze (Cooke, section 2.4, figure 2-5): the platform following
// the viewer, the grab once it stands still, and back.
#include "tests/control/session/session_fixture.h"

namespace igms::control {
namespace {

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

}  // namespace
}  // namespace igms::control
