// Identifying objects from the marks, and the models: removal and undo.
#include "tests/control/session/session_fixture.h"

namespace igms::control {
namespace {

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
  // The next locate carries the model built (it may stand in front of the next object); the
  // database's record of it does not.
  FourMarks();
  const auto next = All<LocateEffect>(Voice(devices::VOICE_BOX, 2));
  ASSERT_EQ(next.size(), 1u);
  ASSERT_EQ(next[0].request.known_size(), 1);
  const object::KnownSolid& known = next[0].request.known(0);
  EXPECT_EQ(known.name(), "cylinder 1");
  EXPECT_EQ(known.type(), object::OBJECT_TYPE_CYLINDER);
  EXPECT_EQ(known.cylinder().center().x(), stored[0].model.cylinder.center().x());
  const auto second =
      All<StoreModelEffect>(Send(LocateReply{next[0].call, Found({5, 2, 3}), now_}));
  ASSERT_EQ(second.size(), 1u);
  EXPECT_EQ(second[0].provenance.request.known_size(), 0);
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

}  // namespace
}  // namespace igms::control
