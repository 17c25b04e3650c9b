#include "device_daemons/voice/audio.h"

#include <gtest/gtest.h>
#include <sndfile.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "device_daemons/voice/endpointer.h"
#include "device_daemons/voice/speech_synth.h"

namespace igms::voice {
namespace {

std::vector<int16_t> Sine(double hz, int rate, double seconds, double amplitude = 10000) {
  std::vector<int16_t> out(static_cast<size_t>(rate * seconds));
  for (size_t i = 0; i < out.size(); ++i) {
    out[i] = static_cast<int16_t>(
        amplitude * std::sin(2 * std::numbers::pi * hz * static_cast<double>(i) / rate));
  }
  return out;
}

int ZeroCrossings(const std::vector<int16_t>& s) {
  int n = 0;
  for (size_t i = 1; i < s.size(); ++i) n += (s[i - 1] < 0) != (s[i] < 0);
  return n;
}

TEST(Audio, ResampleKeepsFrequencyAndLevel) {
  const auto in = Sine(1000, 22050, 1.0);
  const auto out = Resample(in, 22050, 16000);
  ASSERT_EQ(out.size(), 16000u);
  // 1 kHz for 1 s: 2000 crossings whatever the rate.
  EXPECT_NEAR(ZeroCrossings(out), 2000, 4);
  EXPECT_NEAR(RmsDbfs(out), RmsDbfs(in), 0.3);
}

TEST(Audio, ResampleRemovesWhatTheNewRateCannotHold) {
  // 7.9 kHz is fine at 22.05 kHz and above the 16 kHz Nyquist band's cut-off (7.2 kHz).
  const auto out = Resample(Sine(7900, 22050, 0.5), 22050, 16000);
  EXPECT_LT(RmsDbfs(out), RmsDbfs(Sine(7900, 22050, 0.5)) - 20.0);
}

TEST(Audio, ResampleEdgeCases) {
  EXPECT_TRUE(Resample({}, 8000, 16000).empty());
  const auto same = Sine(440, 16000, 0.1);
  EXPECT_EQ(Resample(same, 16000, 16000), same);
  EXPECT_THROW(Resample(same, 0, 16000), std::invalid_argument);
  EXPECT_TRUE(std::isinf(RmsDbfs({})));
}

TEST(Audio, LoadsStereoFilesAtAnyRateAsModelRateMono) {
  const auto path = std::filesystem::temp_directory_path() / "igms_voice_stereo.wav";
  SF_INFO info{};
  info.samplerate = 44100;
  info.channels = 2;
  info.format = SF_FORMAT_WAV | SF_FORMAT_PCM_16;
  SNDFILE* f = sf_open(path.c_str(), SFM_WRITE, &info);
  ASSERT_NE(f, nullptr);
  const auto mono = Sine(500, 44100, 0.5);
  std::vector<int16_t> stereo;
  for (int16_t s : mono) stereo.insert(stereo.end(), {s, s});
  sf_writef_short(f, stereo.data(), static_cast<sf_count_t>(mono.size()));
  sf_close(f);
  const auto audio = LoadSoundFile(path.string());
  ASSERT_TRUE(audio.ok()) << audio.error();
  EXPECT_EQ(audio->sample_rate, 16000);
  EXPECT_NEAR(audio->seconds(), 0.5, 0.01);
  EXPECT_NEAR(ZeroCrossings(audio->samples), 500, 3);
  std::filesystem::remove(path);
}

TEST(Audio, BadFilesAreReportedNotFatal) {
  const auto missing = LoadSoundFile("/nonexistent/file.wav");
  EXPECT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("/nonexistent/file.wav"), std::string::npos);
  const auto path = std::filesystem::temp_directory_path() / "igms_voice_garbage.wav";
  {
    FILE* f = fopen(path.c_str(), "wb");
    fputs("RIFF this is not a wave file at all", f);
    fclose(f);
  }
  const auto garbage = LoadSoundFile(path.string());
  EXPECT_FALSE(garbage.ok());
  EXPECT_FALSE(garbage.error().empty());
  std::filesystem::remove(path);
}

TEST(Endpointer, CutsAStreamIntoItsUtterances) {
  std::vector<int16_t> stream(8000, 0);  // 0.5 s silence
  std::vector<size_t> spoken;
  for (const char* word : {"freeze", "remove points", "cylinder"}) {
    const auto audio = Synthesize({word, "en-us", 175});
    ASSERT_TRUE(audio.ok()) << audio.error();
    spoken.push_back(audio->samples.size());
    stream.insert(stream.end(), audio->samples.begin(), audio->samples.end());
    stream.insert(stream.end(), 12000, 0);  // 0.75 s pause
  }
  Endpointer endpointer;
  std::vector<std::vector<int16_t>> utterances;
  // Fed in uneven chunks, as a capture device delivers them.
  for (size_t i = 0; i < stream.size(); i += 733) {
    const size_t n = std::min<size_t>(733, stream.size() - i);
    for (auto& u : endpointer.Feed(std::span<const int16_t>(stream).subspan(i, n))) {
      utterances.push_back(std::move(u));
    }
  }
  for (auto& u : endpointer.Flush()) utterances.push_back(std::move(u));
  ASSERT_EQ(utterances.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    // Each holds its word (within the pre-roll and trailing silence).
    EXPECT_GT(utterances[i].size(), spoken[i] * 0.6) << i;
    EXPECT_LT(utterances[i].size(), spoken[i] + 16000) << i;
  }
}

// Six seconds of talk without a pause (a tone stands in) are no command: dropped whole, not
// cut at the 5 s limit into a piece and a tail that starts mid-word. The word after the
// pause still comes through.
TEST(Endpointer, DropsSpeechLongerThanAnyCommand) {
  const auto word = Synthesize({"freeze", "en-us", 175});
  ASSERT_TRUE(word.ok()) << word.error();
  std::vector<int16_t> stream(8000, 0);
  for (int i = 0; i < 6 * 16000; ++i) {
    const double t = i / 16000.0;
    stream.push_back(static_cast<int16_t>(8000 * std::sin(2 * std::numbers::pi * 440 * t)));
  }
  stream.insert(stream.end(), 16000, 0);
  stream.insert(stream.end(), word->samples.begin(), word->samples.end());
  stream.insert(stream.end(), 16000, 0);
  auto cut = [&](bool discard) {
    EndpointerOptions options;
    options.discard_overlong = discard;
    Endpointer endpointer(options);
    auto utterances = endpointer.Feed(stream);
    for (auto& u : endpointer.Flush()) utterances.push_back(std::move(u));
    return utterances;
  };
  const auto dropped = cut(true);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_GT(dropped[0].size(), word->samples.size() * 0.6);
  EXPECT_LT(dropped[0].size(), word->samples.size() + 16000);
  const auto kept = cut(false);  // the old behaviour: the 5 s piece, the tail, the word
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_EQ(kept[0].size(), 5u * 16000);
}

TEST(Endpointer, SilenceAndFlushAreQuiet) {
  Endpointer endpointer;
  EXPECT_TRUE(endpointer.Feed(std::vector<int16_t>(32000, 3)).empty());
  EXPECT_TRUE(endpointer.Flush().empty());
  EndpointerOptions bad;
  bad.start_frames = 0;
  EXPECT_THROW(Endpointer{bad}, std::invalid_argument);
}

TEST(SpeechSynth, RejectsBadRequests) {
  EXPECT_FALSE(Synthesize({"", "en-us", 175}).ok());
  EXPECT_FALSE(Synthesize({"box", "-w", 175}).ok());
  const auto too_slow = Synthesize({"box", "en-us", 10});
  EXPECT_FALSE(too_slow.ok());
  EXPECT_FALSE(too_slow.error().empty());
  SpeechRequest flite{"box", "http://example.com/voice.flitevox", 175};
  flite.synthesizer = Synthesizer::kFlite;
  const auto url = Synthesize(flite);  // a voice's name only: flite would fetch a URL
  EXPECT_FALSE(url.ok());
  EXPECT_NE(url.error().find("flite voice"), std::string::npos) << url.error();
  flite.voice = "no_such_voice";
  const auto unknown = Synthesize(flite);
  EXPECT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().find("flite failed"), std::string::npos) << unknown.error();
}

// flite's voices at 16 kHz, its pace set through words a minute: a slower request is longer.
TEST(SpeechSynth, FliteSpeaksAtTheRequestedPace) {
  SpeechRequest request{"remove points", "slt", 175};
  request.synthesizer = Synthesizer::kFlite;
  const auto normal = Synthesize(request);
  ASSERT_TRUE(normal.ok()) << normal.error();
  request.words_per_minute = 120;
  const auto slow = Synthesize(request);
  ASSERT_TRUE(slow.ok()) << slow.error();
  EXPECT_EQ(normal->sample_rate, 16000);
  EXPECT_GT(normal->samples.size(), 8000u);  // more than half a second of speech
  EXPECT_GT(slow->samples.size(), normal->samples.size() * 1.25);
  EXPECT_GT(RmsDbfs(normal->samples), -40.0);  // speech, not silence
}

}  // namespace
}  // namespace igms::voice
