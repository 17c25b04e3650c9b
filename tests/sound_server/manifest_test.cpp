// The manifest parser and the generated lab bank.
#include "sound_server/manifest.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "sound_server/audio_file.h"
#include "sound_server/bank_generator.h"
#include "tests/support/sound_bank.h"

namespace igms::sound {
namespace {

const char* kGood = R"(format: 1
sample_rate: 16000
sounds:
  - {id: 1, key: click, kind: cue, sox: "synth 0.1 sine 440"}
  - {id: 7, key: hello, kind: speech, text: "Hello.", file: other/hi.wav}
)";

TEST(Manifest, ParsesEntriesAndDefaultsFiles) {
  ManifestResult r = ParseManifest(kGood, "/bank/manifest.yaml");
  ASSERT_TRUE(r.manifest) << r.error;
  EXPECT_EQ(r.manifest->sample_rate, 16000);
  ASSERT_EQ(r.manifest->sounds.size(), 2u);
  EXPECT_EQ(r.manifest->FindKey("click")->file, "cues/click.wav");
  EXPECT_EQ(r.manifest->FindId(7)->kind, SoundKind::kSpeech);
  EXPECT_EQ(r.manifest->FileOf(*r.manifest->FindId(7)), "/bank/other/hi.wav");
  EXPECT_EQ(r.manifest->FindId(2), nullptr);
  EXPECT_EQ(r.manifest->FindKey("nope"), nullptr);
}

struct Bad {
  std::string text;
  std::string expect;  // part of the error message
};

TEST(Manifest, RejectsBadManifestsWithAReason) {
  const std::string head = "format: 1\nsounds:\n";
  const std::vector<Bad> cases = {
      {"[1, 2", "not valid YAML"},
      {"- 1\n- 2\n", "map at the top"},
      {"format: 2\nsounds: [{id: 1, key: a, kind: speech, text: x}]\n", "'format' must be 1"},
      {"format: 1\n", "'sounds' must be a non-empty list"},
      {head + "  - {key: a, kind: cue, sox: x}\n", "needs 'id'"},
      {head + "  - {id: -3, key: a, kind: cue, sox: x}\n", "positive"},
      {head + "  - {id: abc, key: a, kind: cue, sox: x}\n", "'id' has the wrong type"},
      {head + "  - {id: 1, key: Bad-Key, kind: cue, sox: x}\n", "'key' must be"},
      {head + "  - {id: 1, key: a, kind: music, sox: x}\n", "'kind' must be"},
      {head + "  - {id: 1, key: a, kind: cue}\n", "needs 'sox'"},
      {head + "  - {id: 1, key: a, kind: speech}\n", "needs 'text'"},
      {head + "  - {id: 1, key: a, kind: speech, text: x, file: ../../etc/passwd}\n",
       "inside the bank"},
      {head + "  - {id: 1, key: a, kind: speech, text: x}\n  - {id: 1, key: b, kind: "
              "speech, text: y}\n",
       "repeats id 1"},
      {head + "  - {id: 1, key: a, kind: speech, text: x}\n  - {id: 2, key: a, kind: "
              "speech, text: y}\n",
       "repeats key 'a'"},
  };
  for (const Bad& bad : cases) {
    ManifestResult r = ParseManifest(bad.text, "m.yaml");
    EXPECT_FALSE(r.manifest) << bad.text;
    EXPECT_NE(r.error.find(bad.expect), std::string::npos) << r.error;
    EXPECT_NE(r.error.find("m.yaml"), std::string::npos) << r.error;
  }
  EXPECT_NE(LoadManifest("/nonexistent/manifest.yaml").error.find("cannot be read"),
            std::string::npos);
}

// Every sound tables 2.5 and 2.6 name, and one message per failure reason, is in the lab's
// bank and was generated as a readable, audible file.
TEST(LabBank, HoldsEverySoundOfTheThesisAndTheFailureReasons) {
  ManifestResult r = LoadManifest(testing::BankDir() / "manifest.yaml");
  ASSERT_TRUE(r.manifest) << r.error;
  const Manifest& m = *r.manifest;
  for (const char* key :
       {"camera_click", "ricochet", "woodblock", "bell_tree", "introduction_music"}) {
    ASSERT_NE(m.FindKey(key), nullptr) << key;
    EXPECT_EQ(m.FindKey(key)->kind, SoundKind::kCue);
  }
  std::set<std::string> texts;
  std::set<std::string> reasons;
  for (const SoundEntry& e : m.sounds) {
    if (e.kind == SoundKind::kSpeech) texts.insert(e.text);
    if (!e.reason.empty()) reasons.insert(e.reason);
  }
  for (const char* text :
       {"Modeling as box.", "Modeling as cylinder.", "Freezing viewing position.",
        "Unfreezing viewing position.", "Removing points.", "Removing model.", "Please wait.",
        "Locating object.", "Welcome to the virtual reality lab.",
        "This is an interactive computer vision demonstration.",
        "Is object a box or a cylinder?"}) {
    EXPECT_TRUE(texts.count(text)) << text;
  }
  EXPECT_EQ(reasons.size(), 7u);
  for (const char* key : {"server_lost", "device_lost", "device_back"}) {
    EXPECT_NE(m.FindKey(key), nullptr) << key;
  }
  for (const SoundEntry& e : m.sounds) {
    AudioFileResult file = ReadAudioFile(m.FileOf(e));
    ASSERT_TRUE(file.clip) << file.error;
    EXPECT_EQ(file.clip->sample_rate, m.sample_rate) << e.key;
    EXPECT_GT(file.clip->Seconds(), 0.05) << e.key;
    EXPECT_LT(file.clip->Seconds(), 5.0) << e.key;
    EXPECT_GT(RmsLevel(file.clip->samples, 0, SIZE_MAX), 0.03) << e.key;
  }
}

TEST(AudioFile, MissingCorruptAndEmptyFilesAreErrors) {
  const std::filesystem::path dir = igms::testing::FreshTempDir("audiofile");
  EXPECT_NE(ReadAudioFile(dir / "none.wav").error.find("missing"), std::string::npos);
  std::ofstream(dir / "junk.wav") << "RIFF????WAVEjunk";
  AudioFileResult junk = ReadAudioFile(dir / "junk.wav");
  EXPECT_FALSE(junk.clip);
  EXPECT_NE(junk.error.find("not a readable sound file"), std::string::npos) << junk.error;
  std::ofstream(dir / "empty.wav");
  EXPECT_FALSE(ReadAudioFile(dir / "empty.wav").clip);
  std::filesystem::remove_all(dir);
}

// The generator makes each entry with sox or espeak-ng, at the manifest's rate, normalised;
// an entry sox cannot make is reported by name and the others are still made.
TEST(BankGenerator, MakesEachEntryAndReportsTheOnesItCannot) {
  const std::filesystem::path dir = igms::testing::FreshTempDir("generator");
  std::ofstream(dir / "manifest.yaml")
      << "format: 1\nsample_rate: 16000\npeak_db: -6\nsounds:\n"
         "  - {id: 1, key: beep, kind: cue, sox: \"synth 0.25 sine 660\"}\n"
         "  - {id: 2, key: broken, kind: cue, sox: \"synth 0.25 no-such-wave\"}\n"
         "  - {id: 3, key: hello, kind: speech, text: \"Hello.\"}\n";
  ManifestResult m = LoadManifest(dir / "manifest.yaml");
  ASSERT_TRUE(m.manifest) << m.error;
  const GenerateResult result = GenerateBank(*m.manifest, dir / "out");
  EXPECT_EQ(result.generated, 2);
  ASSERT_EQ(result.errors.size(), 1u);
  EXPECT_NE(result.errors[0].find("sound 2 'broken'"), std::string::npos) << result.errors[0];
  EXPECT_FALSE(std::filesystem::exists(dir / "out/cues/broken.wav"));
  EXPECT_TRUE(std::filesystem::exists(dir / "out/manifest.yaml"));
  AudioFileResult beep = ReadAudioFile(dir / "out/cues/beep.wav");
  ASSERT_TRUE(beep.clip) << beep.error;
  EXPECT_EQ(beep.clip->sample_rate, 16000);
  EXPECT_NEAR(beep.clip->Seconds(), 0.25, 0.001);
  // A sine normalised to -6 dBFS peaks at 0.5 and has an RMS of 0.5 / sqrt(2).
  EXPECT_NEAR(RmsLevel(beep.clip->samples, 0, SIZE_MAX), 0.5 / std::sqrt(2.0), 0.01);
  AudioFileResult hello = ReadAudioFile(dir / "out/speech/hello.wav");
  ASSERT_TRUE(hello.clip) << hello.error;
  EXPECT_GT(hello.clip->Seconds(), 0.3);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace igms::sound
