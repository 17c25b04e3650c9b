// The real igms-sound-server process over TCP: overlapping plays mix, stop cuts off, every
// bad request gets an error with a reason, a damaged bank or a missing device is reported
// clearly, and the server goes on serving.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/sound_server/sound_checks.h"
#include "tests/support/sound_bank.h"
#include "tests/support/sound_server_process.h"
#include "tests/support/wait_for.h"

namespace igms::sound {
namespace {

using namespace std::chrono_literals;

AudioClip Source(const std::string& relative) {
  Result<AudioClip> file = ReadAudioFile(testing::BankDir() / relative);
  EXPECT_TRUE(file.ok()) << file.error();
  return file.ok() ? *file : AudioClip{};
}

class ServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = igms::testing::FreshTempDir("server");
    wave_ = dir_ / "capture.wav";
    server_ = std::make_unique<testing::ServerProcess>(
        std::vector<std::string>{"--bank", testing::DamagedBank(dir_).string(), "--output", "wave",
                                 "--wave-file", wave_.string()});
    const uint16_t port = server_->WaitListening();
    ASSERT_NE(port, 0) << server_->Log();
    client_ = std::make_unique<testing::SoundClient>(port);
  }
  void TearDown() override {
    client_.reset();
    server_.reset();
    std::filesystem::remove_all(dir_);
  }
  // Waits until the wave output has written `seconds` more of audio to the file, on the
  // output's own clock (its sample count): what was mixed before then, the writer's buffer
  // included, is in the file. The file's frame count then.
  int64_t WaitCaptured(double seconds) {
    net::Result<StatusResponse> status = client_->Status();
    EXPECT_TRUE(status.ok() && status.value.sample_rate() > 0);
    const int64_t target =
        CapturedFrames(wave_) + static_cast<int64_t>(seconds * status.value.sample_rate());
    EXPECT_TRUE(igms::testing::WaitFor("the capture to grow",
                                       [&] { return CapturedFrames(wave_) >= target; }));
    return CapturedFrames(wave_);
  }
  // The position (ms) of play `id` in the server's status, when it plays.
  std::optional<uint32_t> PositionMs(uint64_t id) {
    net::Result<StatusResponse> status = client_->Status();
    if (!status.ok()) return std::nullopt;
    for (const PlayInfo& p : status.value.plays())
      if (p.play_id() == id && p.playing()) return p.position_ms();
    return std::nullopt;
  }
  // Ends the server (which finishes the file) and returns the capture.
  Capture Finish() {
    client_.reset();
    EXPECT_EQ(server_->Terminate(), 0) << server_->Log();
    std::optional<Capture> capture = ReadCapture(wave_);
    EXPECT_TRUE(capture);
    return capture.value_or(Capture{});
  }

  std::filesystem::path dir_, wave_;
  std::unique_ptr<testing::ServerProcess> server_;
  std::unique_ptr<testing::SoundClient> client_;
};

TEST_F(ServerTest, TwoOverlappingPlaysMix) {
  const int64_t before = CapturedFrames(wave_);
  // Two cues at half volume (their sum stays below full scale), the second 200 ms into the
  // first on the output's clock.
  net::Result<PlayResponse> a = client_->Play("introduction_music", PRIORITY_NORMAL, 0.5f);
  ASSERT_TRUE(a.ok()) << a.status.ToString();
  ASSERT_TRUE(igms::testing::WaitFor("200 ms of the music played", [&] {
    return PositionMs(a.value.play_id()).value_or(0) >= 200;
  }));
  net::Result<PlayResponse> b = client_->Play("ricochet", PRIORITY_NORMAL, 0.5f);
  ASSERT_TRUE(b.ok()) << b.status.ToString();
  // Where the cue began in the music, from the server's positions of both at one moment.
  net::Result<StatusResponse> status = client_->Status();
  ASSERT_TRUE(status.ok());
  EXPECT_EQ(status.value.plays_size(), 2);
  int64_t music_ms = -1, ricochet_ms = -1;
  for (const PlayInfo& p : status.value.plays()) {
    if (p.play_id() == a.value.play_id()) music_ms = p.position_ms();
    if (p.play_id() == b.value.play_id()) ricochet_ms = p.position_ms();
  }
  ASSERT_TRUE(music_ms >= 0 && ricochet_ms >= 0) << status.value.DebugString();
  ASSERT_TRUE(client_->WaitIdle());
  WaitCaptured(0.3);
  const Capture capture = Finish();
  const std::vector<int16_t> window(capture.samples.begin() + before, capture.samples.end());
  const AudioClip music = Source("cues/introduction_music.wav");
  const AudioClip ricochet = Source("cues/ricochet.wav");
  auto [c0, c1] = AudibleSpan(window, testing::kSilence);
  auto [m0, m1] = AudibleSpan(music.samples, testing::kSilence);
  const Alignment at_music = AlignClip(window, music.samples, int64_t(c0) - int64_t(m0) - 64,
                                       int64_t(c0) - int64_t(m0) + 64, 4096);
  EXPECT_GT(at_music.correlation, 0.95);
  const std::vector<double> mixed(window.begin(), window.end());
  std::vector<double> rest = Subtract(mixed, music.samples, at_music.offset, 0.5);
  const std::vector<int16_t> rest16(rest.begin(), rest.end());
  const int rate = capture.sample_rate;
  const int64_t cue_offset = (music_ms - ricochet_ms) * rate / 1000;
  const Alignment at_ricochet =
      AlignClip(rest16, ricochet.samples, at_music.offset + cue_offset - rate / 10,
                at_music.offset + cue_offset + rate / 10, 4096);
  EXPECT_GT(at_ricochet.correlation, 0.98);
  rest = Subtract(rest, ricochet.samples, at_ricochet.offset, 0.5);
  // Both whole, nothing else; and the cue began while the music played.
  EXPECT_LT(RmsOf(rest, c0, c1), 0.02 * RmsOf(mixed, c0, c1));
  EXPECT_LT(at_ricochet.offset, at_music.offset + int64_t(m1));
  // The audio agrees with the positions the server reported (to a few mixing periods).
  EXPECT_NEAR(double(at_ricochet.offset - at_music.offset - cue_offset) / rate, 0.0, 0.05);
}

TEST_F(ServerTest, StopCutsOff) {
  const int64_t before = CapturedFrames(wave_);
  net::Result<PlayResponse> played = client_->Play("demonstration");
  ASSERT_TRUE(played.ok());
  EXPECT_GT(played.value.duration_ms(), 3000u);
  // Stopped 0.7 s in, on the output's clock.
  ASSERT_TRUE(igms::testing::WaitFor("0.7 s of the message played", [&] {
    return PositionMs(played.value.play_id()).value_or(0) >= 700;
  }));
  StopRequest stop;
  stop.set_play_id(played.value.play_id());
  net::Result<StopResponse> stopped = client_->Call<StopResponse>(kStopMethod, stop);
  ASSERT_TRUE(stopped.ok()) << stopped.status.ToString();
  EXPECT_EQ(stopped.value.stopped(), 1u);
  net::Result<StatusResponse> status = client_->Status();
  EXPECT_EQ(status.value.plays_size(), 0);
  const int64_t after_first = WaitCaptured(0.3);
  // Stop everything: a queued message goes too.
  net::Result<PlayResponse> welcome = client_->Play("welcome");
  ASSERT_TRUE(welcome.ok());
  net::Result<PlayResponse> queued = client_->Play("please_wait");
  EXPECT_TRUE(queued.value.queued());
  stopped = client_->Call<StopResponse>(kStopMethod, StopRequest());
  EXPECT_EQ(stopped.value.stopped(), 2u);
  EXPECT_TRUE(client_->WaitIdle(100ms));
  WaitCaptured(0.3);
  const Capture capture = Finish();
  const double rate = capture.sample_rate;
  // The message: the 0.7 s played before the stop (at least 0.5 s of it sound), not its
  // whole 3.3 s.
  const std::vector<int16_t> first(capture.samples.begin() + before,
                                   capture.samples.begin() + after_first);
  auto [c0, c1] = AudibleSpan(first, testing::kSilence);
  EXPECT_GT(static_cast<double>(c1 - c0) / rate, 0.5);
  EXPECT_LT(static_cast<double>(c1 - c0) / rate, played.value.duration_ms() / 1000.0 - 1.0);
  // "welcome": a moment of it, not all of it; then nothing, the queued message included.
  const std::vector<int16_t> second(capture.samples.begin() + after_first, capture.samples.end());
  auto [d0, d1] = AudibleSpan(second, testing::kSilence);
  EXPECT_LT(static_cast<double>(d1 - d0) / rate, welcome.value.duration_ms() / 1000.0 - 0.2);
}

TEST_F(ServerTest, BadRequestsGetAnErrorAndTheServerGoesOn) {
  struct Case {
    PlayRequest request;
    igms::ErrorCode code;
    std::string says;
  };
  std::vector<Case> cases;
  auto add = [&](auto fill, igms::ErrorCode code, std::string says) {
    PlayRequest r;
    fill(r);
    cases.push_back({r, code, std::move(says)});
  };
  add([](PlayRequest&) {}, igms::BAD_REQUEST, "set 'id' or 'key'");
  add([](PlayRequest& r) { r.set_id(0); }, igms::BAD_REQUEST, "id 0");
  add([](PlayRequest& r) { r.set_key(""); }, igms::BAD_REQUEST, "empty sound key");
  add([](PlayRequest& r) { r.set_id(4242); }, igms::NOT_FOUND, "no sound with id 4242");
  add([](PlayRequest& r) { r.set_key("kazoo"); }, igms::NOT_FOUND, "no sound with key 'kazoo'");
  add(
      [](PlayRequest& r) {
        r.set_key("woodblock");
        r.set_volume(NAN);
      },
      igms::BAD_REQUEST, "volume");
  add(
      [](PlayRequest& r) {
        r.set_key("woodblock");
        r.set_volume(-0.1f);
      },
      igms::BAD_REQUEST, "volume");
  add(
      [](PlayRequest& r) {
        r.set_key("woodblock");
        r.set_volume(3.0f);
      },
      igms::BAD_REQUEST, "volume");
  add(
      [](PlayRequest& r) {
        r.set_key("woodblock");
        r.set_priority(static_cast<Priority>(9));
      },
      igms::BAD_REQUEST, "priority");
  add([](PlayRequest& r) { r.set_key("missing_file"); }, igms::UNAVAILABLE, "file is missing");
  add([](PlayRequest& r) { r.set_id(901); }, igms::UNAVAILABLE, "not a readable sound file");
  for (const Case& c : cases) {
    net::Result<PlayResponse> r = client_->Call<PlayResponse>(kPlayMethod, c.request);
    EXPECT_EQ(r.status.code, c.code) << c.says << ": " << r.status.ToString();
    EXPECT_NE(r.status.message.find(c.says), std::string::npos) << r.status.ToString();
  }
  StopRequest stop;
  stop.set_play_id(987654);
  EXPECT_EQ(client_->Call<StopResponse>(kStopMethod, stop).status.code, igms::NOT_FOUND);
  SetVolumeRequest volume;
  volume.set_master_volume(1.5f);
  EXPECT_EQ(client_->Call<SetVolumeResponse>(kSetVolumeMethod, volume).status.code,
            igms::BAD_REQUEST);
  volume.set_master_volume(0.25f);
  net::Result<SetVolumeResponse> set = client_->Call<SetVolumeResponse>(kSetVolumeMethod, volume);
  ASSERT_TRUE(set.ok());
  EXPECT_FLOAT_EQ(set.value.master_volume(), 0.25f);
  net::Result<StatusResponse> status = client_->Status();
  ASSERT_TRUE(status.ok());
  EXPECT_EQ(status.value.output(), "wave");
  // The engine counts the refusals that reached it: all but the four malformed requests.
  EXPECT_EQ(status.value.plays_refused(), cases.size() - 4);
  EXPECT_EQ(status.value.plays_started(), 0u);
  EXPECT_FLOAT_EQ(status.value.master_volume(), 0.25f);
  // The damaged sounds are listed, with the reason; the rest are playable.
  net::Result<ListBankResponse> bank =
      client_->Call<ListBankResponse>(kListBankMethod, ListBankRequest());
  ASSERT_TRUE(bank.ok());
  int unavailable = 0;
  for (const BankEntry& e : bank.value.sounds()) {
    if (!e.available()) {
      ++unavailable;
      EXPECT_GE(e.id(), 900u);
      EXPECT_FALSE(e.error().empty());
    }
  }
  EXPECT_EQ(unavailable, 2);
  // ...and the start-up log said so.
  EXPECT_NE(server_->Log().find("'missing_file' cannot be played"), std::string::npos);
  EXPECT_TRUE(client_->Play("woodblock").ok());
  Finish();
}

struct StartCase {
  std::vector<std::string> args;
  int exit_status;
  std::string says;
};

TEST(ServerStart, FailsClearlyOnABadBankOrNoDevice) {
  const std::filesystem::path dir = igms::testing::FreshTempDir("start");
  std::ofstream(dir / "bad.yaml") << "format: 1\nsounds:\n  - {id: 1, key: x, kind: cue}\n";
  const std::vector<StartCase> cases = {
      {{"--bank", (dir / "none.yaml").string(), "--output", "null"}, 2, "cannot be read"},
      {{"--bank", (dir / "bad.yaml").string(), "--output", "null"}, 2, "needs 'sox'"},
      {{"--output", "loudspeaker"}, 2, "unknown output 'loudspeaker'"},
      {{"--output", "wave"}, 2, "needs a file"},
      {{"--device", "no such device"}, 3, "no audio device"},
      {{"--output", "wave", "--wave-file", "/nonexistent/dir/out.wav"}, 3, "cannot write"},
  };
  for (const StartCase& c : cases) {
    testing::ServerProcess server(c.args);
    EXPECT_EQ(server.Wait(), c.exit_status) << server.Log();
    EXPECT_NE(server.Log().find(c.says), std::string::npos) << server.Log();
  }
  std::filesystem::remove_all(dir);
}

TEST(ServerStart, FallsBackToTheNullOutputWhenNoDeviceOpens) {
  const std::filesystem::path dir = igms::testing::FreshTempDir("fallback");
  testing::ServerProcess server({"--device", "no such device", "--fallback", "null"});
  const uint16_t port = server.WaitListening();
  ASSERT_NE(port, 0) << server.Log();
  EXPECT_NE(server.Log().find("no audio device"), std::string::npos);
  EXPECT_NE(server.Log().find("falling back to the null output"), std::string::npos);
  {
    testing::SoundClient client(port);
    net::Result<StatusResponse> status = client.Status();
    ASSERT_TRUE(status.ok());
    EXPECT_EQ(status.value.output(), "null");
    EXPECT_EQ(status.value.device(), "No Output");
    net::Result<PlayResponse> played = client.Play("camera_click");
    EXPECT_TRUE(played.ok()) << played.status.ToString();
    EXPECT_TRUE(client.WaitIdle());
  }
  EXPECT_EQ(server.Terminate(), 0);
  std::filesystem::remove_all(dir);
}

TEST(ServerStart, ReadsItsSectionOfTheLabConfiguration) {
  const std::filesystem::path dir = igms::testing::FreshTempDir("config");
  testing::DamagedBank(dir);
  // An unquoted `null` is a YAML null: still the null output.
  std::ofstream(dir / "lab.yaml") << "processes:\n"
                                     "  sound:\n"
                                     "    bank: manifest.yaml\n"
                                     "    device: no such device\n"
                                     "    fallback: null\n"
                                     "    cue_sources: 2\n"
                                     "    speech_queue: 3\n"
                                     "    volume: 0.5\n";
  testing::ServerProcess server({"--config", (dir / "lab.yaml").string(), "--name", "sound"});
  const uint16_t port = server.WaitListening();
  ASSERT_NE(port, 0) << server.Log();
  {
    testing::SoundClient client(port);
    net::Result<StatusResponse> status = client.Status();
    ASSERT_TRUE(status.ok());
    EXPECT_EQ(status.value.output(), "null");
    EXPECT_EQ(status.value.cue_sources(), 2u);
    EXPECT_EQ(status.value.speech_queue_limit(), 3u);
    EXPECT_FLOAT_EQ(status.value.master_volume(), 0.5f);
    net::Result<ListBankResponse> bank =
        client.Call<ListBankResponse>(kListBankMethod, ListBankRequest());
    ASSERT_TRUE(bank.ok());
    EXPECT_EQ(std::filesystem::path(bank.value.manifest()), dir / "manifest.yaml");
    // The queue holds three messages behind the one being said; the fifth is refused.
    for (int i = 0; i < 4; ++i) EXPECT_TRUE(client.Play("welcome").ok()) << i;
    net::Result<PlayResponse> full = client.Play("welcome");
    EXPECT_EQ(full.status.code, igms::UNAVAILABLE);
    EXPECT_NE(full.status.message.find("queue is full"), std::string::npos);
  }
  EXPECT_EQ(server.Terminate(), 0);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace igms::sound
