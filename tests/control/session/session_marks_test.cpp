// Pointing in the frozen view (Cooke, table 2.2): the stick, ranging, and the marks.
#include "tests/control/session/session_fixture.h"

namespace igms::control {
namespace {

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

}  // namespace
}  // namespace igms::control
