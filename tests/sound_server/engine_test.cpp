// The playback engine in this process, on OpenAL Soft's wave output: what the engine plays
// is checked in the captured file against the bank's own audio. One output per process, so
// every test shares one engine and waits for it to fall idle.
#include "sound_server/engine.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <optional>

#include "sound_server/audio_file.h"
#include "sound_server/wave_capture.h"
#include "tests/sound_server/sound_checks.h"
#include "tests/support/sound_bank.h"
#include "tests/support/wait_for.h"

namespace igms::sound {
namespace {

using namespace std::chrono_literals;
constexpr int kRate = 22050;

class EngineTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(igms::testing::FreshTempDir("engine"));
    wave_ = new std::filesystem::path(*dir_ / "capture.wav");
    Result<Manifest> manifest = LoadManifest(testing::DamagedBank(*dir_));
    ASSERT_TRUE(manifest.ok()) << manifest.error();
    OutputOptions out;
    out.output = "wave";
    out.wave_file = wave_->string();
    out.wave_rate = kRate;
    OutputResult opened = OpenOutput(out);
    ASSERT_TRUE(opened.output) << opened.error;
    EngineResult created = Engine::Create(*manifest, std::move(opened.output));
    ASSERT_TRUE(created.engine) << created.error;
    warnings_ = new std::vector<std::string>(created.warnings);
    engine_ = created.engine.release();
  }
  static void TearDownTestSuite() {
    delete engine_;
    std::filesystem::remove_all(*dir_);
  }
  void SetUp() override {
    ASSERT_NE(engine_, nullptr);
    engine_->Stop(0);
  }

  static AudioClip Source(const std::string& key) {
    Result<AudioClip> file =
        ReadAudioFile(engine_->manifest().FileOf(*engine_->manifest().FindKey(key)));
    EXPECT_TRUE(file.ok()) << file.error();
    return file.ok() ? *file : AudioClip{};
  }
  static void WaitIdle(std::chrono::milliseconds limit = 10s) {
    EXPECT_TRUE(igms::testing::WaitFor(
        "the engine idle", [] { return engine_->Idle(); }, limit));
  }
  // Waits until the wave output has written `seconds` more of audio to the file, on the
  // output's own clock (its sample count): what was mixed before then, the writer's buffer
  // included, is in the file. The file's frame count then.
  static int64_t WaitCaptured(double seconds) {
    const int64_t target = CapturedFrames(*wave_) + static_cast<int64_t>(seconds * kRate);
    EXPECT_TRUE(igms::testing::WaitFor("the capture to grow",
                                       [&] { return CapturedFrames(*wave_) >= target; }));
    return CapturedFrames(*wave_);
  }
  // The position of play `id` (seconds), when it plays.
  static std::optional<double> Position(uint64_t id) {
    for (const PlayState& p : engine_->Status().plays)
      if (p.play_id == id && p.playing) return p.position;
    return std::nullopt;
  }
  // Plays `key`, waits for the end plus a gap, returns the captured frames around it.
  static std::vector<int16_t> PlayAndCapture(const PlayParams& params) {
    const int64_t before = CapturedFrames(*wave_);
    PlayOutcome played = engine_->Play(params);
    EXPECT_TRUE(played.outcome.ok()) << played.outcome.message;
    WaitIdle();
    return Window(before, WaitCaptured(0.3));
  }
  static std::vector<int16_t> Window(int64_t from, int64_t to) {
    std::optional<Capture> capture = ReadCapture(*wave_);
    EXPECT_TRUE(capture);
    if (!capture) return {};
    EXPECT_EQ(capture->sample_rate, kRate);
    to = std::min<int64_t>(to, static_cast<int64_t>(capture->samples.size()));
    return {capture->samples.begin() + std::max<int64_t>(from, 0), capture->samples.begin() + to};
  }

  static Engine* engine_;
  static std::filesystem::path* dir_;
  static std::filesystem::path* wave_;
  static std::vector<std::string>* warnings_;
};
Engine* EngineTest::engine_ = nullptr;
std::filesystem::path* EngineTest::dir_ = nullptr;
std::filesystem::path* EngineTest::wave_ = nullptr;
std::vector<std::string>* EngineTest::warnings_ = nullptr;

using testing::ExpectSameSound;
using testing::kSilence;

TEST_F(EngineTest, EachCueAndAMessagePlayAsGenerated) {
  for (const char* key : {"camera_click", "ricochet", "woodblock", "bell_tree",
                          "introduction_music", "please_wait"}) {
    PlayParams params;
    params.sound.key = key;
    ExpectSameSound(PlayAndCapture(params), Source(key), 1.0, key);
  }
}

TEST_F(EngineTest, VolumeScalesTheLevel) {
  PlayParams params;
  params.sound.id = engine_->manifest().FindKey("ricochet")->id;
  params.volume = 0.5f;
  ExpectSameSound(PlayAndCapture(params), Source("ricochet"), 0.5, "ricochet at half volume");
}

TEST_F(EngineTest, ACueOverSpeechMixesBoth) {
  const int64_t before = CapturedFrames(*wave_);
  PlayParams speech, cue;
  speech.sound.key = "please_wait";
  cue.sound.key = "ricochet";
  speech.volume = cue.volume = 0.5f;  // the sum stays below full scale
  const PlayOutcome said = engine_->Play(speech);
  ASSERT_TRUE(said.outcome.ok());
  // The cue starts 0.3 s into the message, on the output's clock.
  ASSERT_TRUE(igms::testing::WaitFor("0.3 s of the message played",
                                     [&] { return Position(said.play_id).value_or(0) >= 0.3; }));
  const PlayOutcome sounded = engine_->Play(cue);
  ASSERT_TRUE(sounded.outcome.ok());
  // Where the cue began in the message, from the engine's positions of both at one moment.
  const std::optional<double> speech_at = Position(said.play_id),
                              cue_at = Position(sounded.play_id);
  ASSERT_TRUE(speech_at && cue_at);
  EXPECT_EQ(engine_->Status().plays.size(), 2u);
  const int64_t cue_offset = std::lround((*speech_at - *cue_at) * kRate);
  WaitIdle();
  const std::vector<int16_t> window = Window(before, WaitCaptured(0.3));
  const AudioClip a = Source("please_wait"), b = Source("ricochet");
  // Find the message, take it away, then find the cue in what is left: both must be there
  // whole, and nothing else.
  auto [c0, c1] = AudibleSpan(window, kSilence);
  auto [a0, a1] = AudibleSpan(a.samples, kSilence);
  Alignment at_a = AlignClip(window, a.samples, int64_t(c0) - int64_t(a0) - 64,
                             int64_t(c0) - int64_t(a0) + 64, 4096);
  EXPECT_GT(at_a.correlation, 0.95);
  std::vector<double> mixed(window.begin(), window.end());
  std::vector<double> rest = Subtract(mixed, a.samples, at_a.offset, 0.5);
  std::vector<int16_t> rest16(rest.begin(), rest.end());
  Alignment at_b = AlignClip(rest16, b.samples, at_a.offset + cue_offset - kRate / 10,
                             at_a.offset + cue_offset + kRate / 10, 4096);
  EXPECT_GT(at_b.correlation, 0.98);
  // The audio agrees with the positions the engine reported (to a few mixing periods).
  EXPECT_NEAR(double(at_b.offset - at_a.offset - cue_offset) / kRate, 0.0, 0.05);
  rest = Subtract(rest, b.samples, at_b.offset, 0.5);
  EXPECT_LT(RmsOf(rest, c0, c1), 0.02 * RmsOf(mixed, c0, c1));
  // The cue started inside the message: they really overlapped.
  EXPECT_LT(at_b.offset, at_a.offset + int64_t(a1));
}

TEST_F(EngineTest, StopCutsASoundOff) {
  const int64_t before = CapturedFrames(*wave_);
  PlayParams params;
  params.sound.key = "welcome";
  PlayOutcome played = engine_->Play(params);
  ASSERT_TRUE(played.outcome.ok());
  // Stopped 0.6 s in, on the output's clock.
  ASSERT_TRUE(igms::testing::WaitFor("0.6 s of the message played",
                                     [&] { return Position(played.play_id).value_or(0) >= 0.6; }));
  size_t stopped = 0;
  EXPECT_TRUE(engine_->Stop(played.play_id, &stopped).ok());
  EXPECT_EQ(stopped, 1u);
  EXPECT_TRUE(engine_->Idle());
  const std::vector<int16_t> window = Window(before, WaitCaptured(0.3));
  auto [c0, c1] = AudibleSpan(window, kSilence);
  const AudioClip whole = Source("welcome");
  auto [w0, w1] = AudibleSpan(whole.samples, kSilence);
  const double heard = double(c1 - c0) / kRate;
  // What played before the stop was heard (at least 0.3 s of sound in its first 0.6 s),
  // and the rest of its more than 2 s was not.
  EXPECT_GT(heard, 0.3);
  EXPECT_GT(whole.Seconds(), 2.0);
  EXPECT_LT(heard, double(w1 - w0) / kRate - 1.0);
  EXPECT_EQ(engine_->Stop(played.play_id).failure, Failure::kNotFound);
}

TEST_F(EngineTest, MessagesQueueAndAPromptInterrupts) {
  PlayParams first, second, prompt;
  first.sound.key = "welcome";
  second.sound.key = "please_wait";
  prompt.sound.key = "box_or_cylinder";
  prompt.priority = PlayPriority::kHigh;
  PlayOutcome p1 = engine_->Play(first);
  PlayOutcome p2 = engine_->Play(second);
  ASSERT_TRUE(p1.outcome.ok() && p2.outcome.ok());
  EXPECT_FALSE(p1.queued);
  EXPECT_TRUE(p2.queued);
  EXPECT_EQ(p2.queue_position, 1u);
  EngineStatus status = engine_->Status();
  ASSERT_EQ(status.plays.size(), 2u);
  EXPECT_TRUE(status.plays[0].playing);
  EXPECT_EQ(status.plays[0].entry.key, "welcome");
  EXPECT_FALSE(status.plays[1].playing);
  // A cue sounds at once over the message; the prompt cuts both the message and the cue.
  PlayParams cue;
  cue.sound.key = "bell_tree";
  PlayOutcome c = engine_->Play(cue);
  ASSERT_TRUE(c.outcome.ok());
  EXPECT_FALSE(c.queued);
  PlayOutcome p3 = engine_->Play(prompt);
  ASSERT_TRUE(p3.outcome.ok());
  EXPECT_FALSE(p3.queued);
  status = engine_->Status();
  ASSERT_EQ(status.plays.size(), 2u);
  EXPECT_EQ(status.plays[0].play_id, p3.play_id);
  EXPECT_EQ(status.plays[0].priority, PlayPriority::kHigh);
  EXPECT_EQ(status.plays[1].play_id, p2.play_id);  // still waiting its turn
  // After the prompt, the waiting message is said.
  EXPECT_TRUE(igms::testing::WaitFor("the waiting message said", [&] {
    status = engine_->Status();
    return !status.plays.empty() && status.plays[0].play_id == p2.play_id &&
           status.plays[0].playing;
  }));
  engine_->Stop(0);
}

TEST_F(EngineTest, BusyCueSourcesGoToTheMoreImportant) {
  PlayParams high, normal;
  high.sound.key = "introduction_music";
  high.priority = PlayPriority::kHigh;
  normal.sound.key = "woodblock";
  for (int i = 0; i < engine_->Status().cue_sources; ++i)
    ASSERT_TRUE(engine_->Play(high).outcome.ok());
  PlayOutcome refused = engine_->Play(normal);
  EXPECT_EQ(refused.outcome.failure, Failure::kUnavailable);
  EXPECT_NE(refused.outcome.message.find("higher priority"), std::string::npos);
  PlayOutcome taken = engine_->Play(high);
  EXPECT_TRUE(taken.outcome.ok());
  EXPECT_EQ(engine_->Status().plays.size(), size_t(engine_->Status().cue_sources));
  engine_->Stop(0);
  EXPECT_TRUE(engine_->Idle());
}

TEST_F(EngineTest, BadRequestsAreRefusedWithAReason) {
  struct Case {
    PlayParams params;
    Failure failure;
    std::string says;
  };
  std::vector<Case> cases(8);
  cases[0].params.sound.id = 9999;
  cases[0] = {cases[0].params, Failure::kNotFound, "no sound with id 9999"};
  cases[1].params.sound.key = "no_such_sound";
  cases[1] = {cases[1].params, Failure::kNotFound, "no sound with key 'no_such_sound'"};
  cases[2] = {PlayParams{}, Failure::kBadRequest, "give an id or a key"};
  cases[3].params.sound.key = "woodblock";
  cases[3].params.volume = NAN;
  cases[3] = {cases[3].params, Failure::kBadRequest, "volume"};
  cases[4].params.sound.key = "woodblock";
  cases[4].params.volume = 1.5f;
  cases[4] = {cases[4].params, Failure::kBadRequest, "volume"};
  cases[5].params.sound.key = "woodblock";
  cases[5].params.priority = static_cast<PlayPriority>(7);
  cases[5] = {cases[5].params, Failure::kBadRequest, "priority"};
  cases[6].params.sound.key = "missing_file";
  cases[6] = {cases[6].params, Failure::kUnavailable, "missing.wav: file is missing"};
  cases[7].params.sound.id = 901;
  cases[7] = {cases[7].params, Failure::kUnavailable, "corrupt.wav: not a readable"};
  for (const Case& c : cases) {
    PlayOutcome r = engine_->Play(c.params);
    EXPECT_EQ(r.outcome.failure, c.failure) << c.says;
    EXPECT_NE(r.outcome.message.find(c.says), std::string::npos) << r.outcome.message;
  }
  EXPECT_EQ(engine_->Stop(123456).failure, Failure::kNotFound);
  EXPECT_EQ(engine_->SetMasterVolume(-1).failure, Failure::kBadRequest);
  EXPECT_TRUE(engine_->Idle());
  // The damaged entries were reported at start and are listed as unavailable.
  ASSERT_EQ(warnings_->size(), 2u);
  int unavailable = 0;
  for (const BankSound& s : engine_->Bank()) unavailable += s.available ? 0 : 1;
  EXPECT_EQ(unavailable, 2);
}

}  // namespace
}  // namespace igms::sound
