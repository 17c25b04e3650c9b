// The session's start (Cooke, section 2.4): the introduction, the welcome, the peers it
// needs and the options it refuses.
#include "tests/control/session/session_fixture.h"

namespace igms::control {
namespace {

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

}  // namespace
}  // namespace igms::control
