// igms-voiced as a real process through a real TCP subscriber: with its Dragon simulator
// on a real pseudo-terminal, and with the real recogniser hearing espeak-ng speech.
#include <gtest/gtest.h>

#include <filesystem>

#include "common/net/client.h"
#include "device_daemons/serial/recording.h"
#include "igms/devices.pb.h"
#include "tests/device_daemons/voice/pulse_sink.h"
#include "tests/support/daemon_process.h"
#include "tests/support/files.h"
#include "tests/support/io_thread.h"
#include "tests/support/readings.h"
#include "tests/support/wait_for.h"

namespace igms::devices {
namespace {

using igms::testing::WaitFor;
using testing::DaemonProcess;
using namespace std::chrono_literals;

class Connected {
 public:
  explicit Connected(uint16_t port) {
    net::ClientOptions o;
    o.port = port;
    o.name = "voice_daemon_test";
    client_ = std::make_unique<net::Client>(io_.io(), o);
    client_->Start();
  }
  ~Connected() {
    client_->Stop();
    io_.Stop();
  }
  net::Client* operator->() { return client_.get(); }

 private:
  igms::testing::IoThread io_;
  std::unique_ptr<net::Client> client_;
};

// The recogniser answers once it has decoded the phrase: allow it time on a busy machine.
net::Result<SimInjectResponse> Injected(Connected& c, const SimInjectRequest& req) {
  return c->CallSync<SimInjectResponse>("igms.devices.SimService.Inject", req, 30s);
}
net::Status Inject(Connected& c, const SimInjectRequest& req) { return Injected(c, req).status; }
net::Result<SimInjectResponse> Heard(Connected& c, const std::string& phrase) {
  SimInjectRequest req;
  req.set_spoken(phrase);
  return Injected(c, req);
}
net::Status Say(Connected& c, const std::string& phrase) { return Heard(c, phrase).status; }
net::Status SetState(Connected& c, OperatorState state) {
  SetOperatorStateRequest req;
  req.set_state(state);
  return c
      ->CallSync<SetOperatorStateResponse>("igms.devices.VoiceService.SetOperatorState", req, 2s)
      .status;
}
LinkStatus StatusOf(Connected& c) {
  return c->CallSync<LinkStatus>("igms.devices.VoiceService.Status", GetStatusRequest(), 2s).value;
}

TEST(VoiceDaemon, SimulatedDragonThroughPtyAndTcp) {
  const std::string recording = igms::testing::TempPath("voice.rec");
  {
    DaemonProcess daemon("igms-voiced", {"--simulate", "--port", "0", "--record", recording});
    const uint16_t port = daemon.WaitForPort();
    ASSERT_NE(port, 0) << daemon.Log();
    Connected client(port);
    igms::testing::Collected<VoiceState> got;
    client->Subscribe<VoiceState>("igms.devices.VoiceService.Live", SubscribeRequest(),
                                  [&](const VoiceState& s) { got.Add(s); });
    ASSERT_TRUE(WaitFor("the link up", [&] { return StatusOf(client).state() == CONNECTED; }))
        << daemon.Log();

    // An injected command arrives with its code.
    SimInjectRequest freeze;
    freeze.set_voice(VOICE_FREEZE);
    ASSERT_TRUE(Inject(client, freeze).ok());
    ASSERT_TRUE(WaitFor("the first command", [&] { return got.size() == 1; })) << daemon.Log();
    EXPECT_EQ(got.last().command(), VOICE_FREEZE);
    EXPECT_EQ(got.last().state(), VERIFICATION);
    EXPECT_GT(got.last().stamp().receive_monotonic_ns(), 0);

    // The state follows: after freeze the system is building; "box" is not valid there,
    // nor a word that is no command at all.
    ASSERT_TRUE(Say(client, "box").ok());
    ASSERT_TRUE(Say(client, "hello").ok());
    ASSERT_TRUE(Say(client, "mark").ok());
    ASSERT_TRUE(WaitFor("the second command", [&] { return got.size() == 2; }));
    EXPECT_EQ(got.last().command(), VOICE_MARK);
    // The control client says four marks are placed: now "box" is taken.
    ASSERT_TRUE(SetState(client, AWAITING_OBJECT_TYPE).ok());
    ASSERT_TRUE(Say(client, "box").ok());
    ASSERT_TRUE(WaitFor("the third command", [&] { return got.size() == 3; }));
    EXPECT_EQ(got.last().command(), VOICE_BOX);
    EXPECT_EQ(got.last().state(), AWAITING_OBJECT_TYPE);
    // The thesis's flaw: the system is in verification (a button) and the operator says
    // unfreeze; the state request makes "unfreeze" invalid, then valid again.
    ASSERT_TRUE(SetState(client, VERIFICATION).ok());
    ASSERT_TRUE(Say(client, "unfreeze").ok());
    ASSERT_TRUE(SetState(client, MODEL_BUILDING).ok());
    ASSERT_TRUE(Say(client, "unfreeze").ok());
    ASSERT_TRUE(WaitFor("the fourth command", [&] { return got.size() == 4; }));
    EXPECT_EQ(got.last().command(), VOICE_UNFREEZE);

    // A truncated report and garbage mid-stream: counted; the next command still arrives.
    // The truncation falls on the next line out, a probe's answer ("00"; five a second),
    // whose half runs into the answer after it: one byte too many there, counted as garbage.
    const uint64_t garbage_before = StatusOf(client).garbage_bytes();
    SimInjectRequest truncate;
    truncate.mutable_fault()->set_truncate_next(true);
    ASSERT_TRUE(Inject(client, truncate).ok());
    ASSERT_TRUE(WaitFor("the cut probe answer counted as garbage",
                        [&] { return StatusOf(client).garbage_bytes() > garbage_before; }));
    SimInjectRequest fault;
    fault.mutable_fault()->set_garbage_bytes(300);
    ASSERT_TRUE(Inject(client, fault).ok());
    SimInjectRequest solid;
    solid.set_voice(VOICE_SOLID);
    ASSERT_TRUE(Inject(client, solid).ok());
    ASSERT_TRUE(WaitFor("the command after the garbage",
                        [&] { return got.size() >= 5 && got.last().command() == VOICE_SOLID; }));
    // The port vanishes and returns: reopened, commands flow again.
    SimInjectRequest vanish;
    vanish.mutable_fault()->set_vanish_ms(400);
    ASSERT_TRUE(Inject(client, vanish).ok());
    ASSERT_TRUE(WaitFor("the port reopened", [&] { return StatusOf(client).reopens() >= 1; }));
    ASSERT_TRUE(WaitFor(
        "the link up", [&] { return StatusOf(client).state() == CONNECTED; }, 15s));
    SimInjectRequest wire;
    wire.set_voice(VOICE_WIREFRAME);
    ASSERT_TRUE(Inject(client, wire).ok());
    ASSERT_TRUE(WaitFor("the command after reopening",
                        [&] { return got.last().command() == VOICE_WIREFRAME; }));

    // Bad requests: clear errors.
    SimInjectRequest wrong;
    wrong.mutable_joystick()->set_x(1);
    net::Status st = Inject(client, wrong);
    EXPECT_EQ(st.code, igms::BAD_REQUEST);
    EXPECT_NE(st.message.find("spoken"), std::string::npos);
    SimInjectRequest unknown;
    unknown.set_voice(static_cast<VoiceCommand>(45));
    EXPECT_EQ(Inject(client, unknown).code, igms::BAD_REQUEST);
    EXPECT_EQ(SetState(client, OPERATOR_STATE_UNSPECIFIED).code, igms::BAD_REQUEST);
    EXPECT_EQ(daemon.Stop(), 0);
  }
  // Record then replay reproduces the commands.
  auto rec = LoadRecording(recording);
  ASSERT_TRUE(rec.ok()) << rec.error();
  EXPECT_EQ(rec->header.device(), "voice");
  ASSERT_GE(rec->readings.size(), 6u);
  DaemonProcess replay("igms-voiced",
                       {"--replay", recording, "--replay-speed", "0", "--port", "0"});
  const uint16_t port = replay.WaitForPort();
  ASSERT_NE(port, 0) << replay.Log();
  Connected client(port);
  ASSERT_TRUE(WaitFor("the replay to finish",
                      [&] { return StatusOf(client).message() == "replay finished"; }));
  const LinkStatus st = StatusOf(client);
  EXPECT_EQ(st.state(), REPLAYING);
  EXPECT_EQ(st.readings(), rec->readings.size());
  EXPECT_EQ(replay.Stop(), 0);
  std::filesystem::remove(recording);
}

// SimInjectResponse.heard: what the simulated Dragon made of each phrase, so a script can
// check it without watching the stream.
TEST(VoiceDaemon, SimulatedDragonSaysWhatItHeard) {
  DaemonProcess daemon("igms-voiced", {"--simulate", "--port", "0"});
  const uint16_t port = daemon.WaitForPort();
  ASSERT_NE(port, 0) << daemon.Log();
  Connected client(port);
  igms::testing::Collected<VoiceState> got;
  client->Subscribe<VoiceState>("igms.devices.VoiceService.Live", SubscribeRequest(),
                                [&](const VoiceState& s) { got.Add(s); });
  ASSERT_TRUE(WaitFor("the Dragon connected", [&] {
    return StatusOf(client).state() == CONNECTED;
  })) << daemon.Log();

  auto freeze = Heard(client, "freeze");
  ASSERT_TRUE(freeze.ok()) << freeze.status.message;
  EXPECT_TRUE(freeze.value.heard().accepted());
  EXPECT_EQ(freeze.value.heard().command(), VOICE_FREEZE);
  EXPECT_EQ(freeze.value.heard().text(), "freeze");
  EXPECT_EQ(freeze.value.heard().state(), VERIFICATION);
  EXPECT_EQ(freeze.value.heard().detail(), "");
  ASSERT_TRUE(WaitFor("the first command", [&] { return got.size() == 1; })) << daemon.Log();
  EXPECT_EQ(got.last().command(), VOICE_FREEZE);

  // Frozen: "box" is a command, but not one the model-building grammar takes.
  auto box = Heard(client, "box");
  ASSERT_TRUE(box.ok()) << box.status.message;
  EXPECT_FALSE(box.value.heard().accepted());
  EXPECT_EQ(box.value.heard().command(), VOICE_BOX);
  EXPECT_EQ(box.value.heard().state(), MODEL_BUILDING);
  EXPECT_NE(box.value.heard().detail().find("not valid in state"), std::string::npos)
      << box.value.heard().detail();
  auto hello = Heard(client, "hello");
  ASSERT_TRUE(hello.ok()) << hello.status.message;
  EXPECT_FALSE(hello.value.heard().accepted());
  EXPECT_EQ(hello.value.heard().command(), VOICE_COMMAND_UNSPECIFIED);
  EXPECT_NE(hello.value.heard().detail().find("\"hello\" is no command"), std::string::npos)
      << hello.value.heard().detail();
  // A command by its code is heard too.
  SimInjectRequest mark;
  mark.set_voice(VOICE_MARK);
  auto marked = Injected(client, mark);
  ASSERT_TRUE(marked.ok()) << marked.status.message;
  EXPECT_TRUE(marked.value.heard().accepted());
  EXPECT_EQ(marked.value.heard().command(), VOICE_MARK);
  ASSERT_TRUE(WaitFor("the second command", [&] { return got.size() == 2; })) << daemon.Log();
  EXPECT_EQ(got.last().command(), VOICE_MARK);
  EXPECT_EQ(daemon.Stop(), 0);
}

TEST(VoiceDaemon, RecogniserGrammarFollowsTheStateRequest) {
  DaemonProcess daemon(
      "igms-voiced",
      {"--wav", std::string(std::getenv("IGMS_SOURCE_DIR")) + "/README.md", "--port", "0"});
  EXPECT_EQ(daemon.WaitExit(), 1);  // not a sound file: a clear error, no crash
  EXPECT_NE(daemon.Log().find("README.md"), std::string::npos) << daemon.Log();

  DaemonProcess bad("igms-voiced", {"--microphone", "--simulate", "--port", "0"});
  EXPECT_EQ(bad.WaitExit(), 2);
  // This machine has no capture device: a clear error and exit status 1, no hang.
  setenv("ALSOFT_DRIVERS", "null", 1);
  DaemonProcess no_microphone("igms-voiced", {"--microphone", "--port", "0"});
  EXPECT_EQ(no_microphone.WaitExit(), 1);
  EXPECT_NE(no_microphone.Log().find("microphone"), std::string::npos) << no_microphone.Log();
  unsetenv("ALSOFT_DRIVERS");

  // The recogniser with no input of its own: spoken phrases come from the sim service.
  const std::string wav = igms::testing::TempPath("freeze.wav");
  ASSERT_EQ(std::system(("espeak-ng -v en-us -w " + wav + " freeze").c_str()), 0);
  // The lab file's model_dir (an operator's adapted model) reaches the recogniser: a folder
  // that holds no model is named in the error.
  const std::string lab = igms::testing::TempPath("voice-lab.yaml");
  igms::testing::WriteFile(lab,
                           "processes:\n"
                           "  voice: {program: igms-voiced, host: 127.0.0.1, port: 0,\n"
                           "          model_dir: /nonexistent/igms-model}\n");
  DaemonProcess no_model("igms-voiced", {"--config", lab, "--name", "voice", "--wav", wav});
  EXPECT_NE(no_model.WaitExit(), 0);
  EXPECT_NE(no_model.Log().find("/nonexistent/igms-model"), std::string::npos) << no_model.Log();
  DaemonProcess recogniser("igms-voiced", {"--wav", wav, "--wav-interval-ms", "0", "--port", "0"});
  const uint16_t port = recogniser.WaitForPort(60s);
  ASSERT_NE(port, 0) << recogniser.Log();
  Connected client(port);
  igms::testing::Collected<VoiceState> got;
  client->Subscribe<VoiceState>("igms.devices.VoiceService.Live", SubscribeRequest(),
                                [&](const VoiceState& s) { got.Add(s); });
  // The file: "freeze", heard in verification.
  ASSERT_TRUE(WaitFor(
      "the first command", [&] { return got.size() == 1; }, 30s))
      << recogniser.Log();
  EXPECT_EQ(got.last().command(), VOICE_FREEZE);
  EXPECT_GT(got.last().confidence(), 0.0);
  EXPECT_GT(got.last().stamp().device_time_us(), 0u);
  // The control client says the system is back in verification: "box" is not valid there
  // and is rejected; once the type is awaited it is taken.
  // The answer comes once the phrase is decoded, saying what was heard.
  ASSERT_TRUE(SetState(client, VERIFICATION).ok());
  auto rejected = Heard(client, "box");
  ASSERT_TRUE(rejected.ok()) << rejected.status.message;
  EXPECT_FALSE(rejected.value.heard().accepted());
  EXPECT_EQ(rejected.value.heard().command(), VOICE_BOX);
  EXPECT_EQ(rejected.value.heard().state(), VERIFICATION);
  EXPECT_NE(rejected.value.heard().detail().find("not valid in state verification"),
            std::string::npos)
      << rejected.value.heard().detail();
  ASSERT_TRUE(WaitFor(
      "the rejected utterance counted",
      [&] { return StatusOf(client).message().find("1 rejected") != std::string::npos; }, 30s))
      << StatusOf(client).message();
  EXPECT_NE(StatusOf(client).message().find("not valid in state verification"), std::string::npos);
  EXPECT_EQ(got.size(), 1u);
  ASSERT_TRUE(SetState(client, AWAITING_OBJECT_TYPE).ok());
  auto accepted = Heard(client, "box");
  ASSERT_TRUE(accepted.ok()) << accepted.status.message;
  EXPECT_TRUE(accepted.value.heard().accepted()) << accepted.value.heard().detail();
  EXPECT_EQ(accepted.value.heard().command(), VOICE_BOX);
  EXPECT_EQ(accepted.value.heard().state(), AWAITING_OBJECT_TYPE);
  EXPECT_GT(accepted.value.heard().confidence(), 0.0);
  EXPECT_NE(accepted.value.heard().text().find("box"), std::string::npos)
      << accepted.value.heard().text();
  ASSERT_TRUE(WaitFor(
      "the second command", [&] { return got.size() == 2; }, 30s))
      << StatusOf(client).message();
  EXPECT_EQ(got.last().command(), VOICE_BOX);
  EXPECT_EQ(got.last().state(), AWAITING_OBJECT_TYPE);
  EXPECT_EQ(Inject(client,
                   [] {
                     SimInjectRequest r;
                     r.mutable_fault()->set_garbage_bytes(3);
                     return r;
                   }())
                .code,
            igms::BAD_REQUEST);
  EXPECT_EQ(recogniser.Stop(), 0);
  std::filesystem::remove(wav);
}

// The microphone path for real (pulse_sink.h): espeak-ng's words played into a private
// PulseAudio server's null sink, whose monitor the daemon captures.
TEST(VoiceDaemon, HearsCommandsThroughAMicrophone) {
  ASSERT_TRUE(igms::testing::PulseSink::ToolsPresent())
      << "pulseaudio or paplay is missing: deploy/install-deps.sh installs pulseaudio and "
         "pulseaudio-utils";
  igms::testing::PulseSink sink;
  ASSERT_TRUE(sink.WaitReady()) << sink.Log();

  const std::string freeze = sink.File("freeze.wav"), range = sink.File("range.wav");
  ASSERT_EQ(std::system(("espeak-ng -v en-us -w " + freeze + " freeze").c_str()), 0);
  ASSERT_EQ(std::system(("espeak-ng -v en-us -w " + range + " range").c_str()), 0);
  DaemonProcess daemon("igms-voiced", {"--microphone", "--port", "0"});
  const uint16_t port = daemon.WaitForPort(60s);
  ASSERT_NE(port, 0) << daemon.Log() << sink.Log();
  Connected client(port);
  igms::testing::Collected<VoiceState> got;
  client->Subscribe<VoiceState>("igms.devices.VoiceService.Live", SubscribeRequest(),
                                [&](const VoiceState& s) { got.Add(s); });
  ASSERT_TRUE(WaitFor(
      "the link up", [&] { return StatusOf(client).state() == CONNECTED; }, 20s))
      << StatusOf(client).message() << daemon.Log();
  // A word is said again when it was not taken, as an operator would: on a loaded machine
  // the captured audio can reach the recogniser less clean than the file (it rejected a
  // "freeze" once for 120 ms of speech it could not explain). A wrong command is never
  // acceptable.
  auto hear = [&](const std::string& wav, VoiceCommand want) {
    const size_t before = got.size();
    for (int attempt = 0; attempt < 3; ++attempt) {
      if (!sink.Play(wav)) return false;
      if (WaitFor(
              "a command", [&] { return got.size() > before; }, 5s))
        return got.size() == before + 1 && got.last().command() == want;
    }
    return false;
  };
  // "freeze" in verification, then "range" once frozen (the state the daemon predicts).
  ASSERT_TRUE(hear(freeze, VOICE_FREEZE)) << daemon.Log();
  ASSERT_TRUE(hear(range, VOICE_RANGE)) << daemon.Log();
  EXPECT_EQ(got.size(), 2u);

  // The sound server going away is the microphone unplugged: the daemon says so and keeps
  // serving, and no command is made up.
  sink.Stop();
  EXPECT_TRUE(WaitFor(
      "the lost microphone reported", [&] { return StatusOf(client).state() == REOPENING; }, 30s))
      << StatusOf(client).message() << daemon.Log();
  EXPECT_EQ(got.size(), 2u);
  EXPECT_FALSE(daemon.Exited()) << daemon.Log();
}

}  // namespace
}  // namespace igms::devices
