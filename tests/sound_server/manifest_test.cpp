// The manifest parser and the generated lab bank.
#include "sound_server/manifest.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "igms/object.pb.h"
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
  Result<Manifest> r = ParseManifest(kGood, "/bank/manifest.yaml");
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->sample_rate, 16000);
  ASSERT_EQ(r->sounds.size(), 2u);
  EXPECT_EQ(r->FindKey("click")->file, "cues/click.wav");
  EXPECT_EQ(r->FindId(7)->kind, SoundKind::kSpeech);
  EXPECT_EQ(r->FileOf(*r->FindId(7)), "/bank/other/hi.wav");
  EXPECT_EQ(r->FindId(2), nullptr);
  EXPECT_EQ(r->FindKey("nope"), nullptr);
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
    Result<Manifest> r = ParseManifest(bad.text, "m.yaml");
    EXPECT_FALSE(r.ok()) << bad.text;
    EXPECT_NE(r.error().find(bad.expect), std::string::npos) << r.error();
    EXPECT_NE(r.error().find("m.yaml"), std::string::npos) << r.error();
  }
  EXPECT_NE(LoadManifest("/nonexistent/manifest.yaml").error().find("cannot be read"),
            std::string::npos);
}

// Every sound tables 2.5 and 2.6 name, and one message per failure reason, is in the lab's
// bank and was generated as a readable, audible file.
TEST(LabBank, HoldsEverySoundOfTheThesisAndTheFailureReasons) {
  Result<Manifest> r = LoadManifest(testing::BankDir() / "manifest.yaml");
  ASSERT_TRUE(r.ok()) << r.error();
  const Manifest& m = *r;
  for (const char* key :
       {"camera_click", "ricochet", "woodblock", "bell_tree", "introduction_music", "unmark"}) {
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
  EXPECT_EQ(reasons.size(), 12u);
  for (const char* key : {"no_echo", "server_lost", "server_back", "device_lost", "device_back"}) {
    ASSERT_NE(m.FindKey(key), nullptr) << key;
    EXPECT_EQ(m.FindKey(key)->kind, SoundKind::kSpeech) << key;
  }
  for (const SoundEntry& e : m.sounds) {
    Result<AudioClip> file = ReadAudioFile(m.FileOf(e));
    ASSERT_TRUE(file.ok()) << file.error();
    EXPECT_EQ(file->sample_rate, m.sample_rate) << e.key;
    EXPECT_GT(file->Seconds(), 0.05) << e.key;
    EXPECT_LT(file->Seconds(), 5.0) << e.key;
    EXPECT_GT(RmsLevel(file->samples, 0, SIZE_MAX), 0.03) << e.key;
  }
}

// The control client speaks the message whose `reason` is the failure's reason code by its
// enum value name: every FailureReason of igms/object.proto but FAILURE_NONE has exactly one
// spoken message, and no message names a reason the enum does not have.
TEST(LabBank, HasOneMessageForEveryFailureReasonByItsEnumName) {
  const igms::Result<Manifest> r = LoadManifest(testing::BankDir() / "manifest.yaml");
  ASSERT_TRUE(r.ok()) << r.error();
  const google::protobuf::EnumDescriptor* reasons = igms::object::FailureReason_descriptor();
  ASSERT_GT(reasons->value_count(), 1);
  for (int i = 0; i < reasons->value_count(); ++i) {
    const google::protobuf::EnumValueDescriptor* reason = reasons->value(i);
    int messages = 0;
    for (const SoundEntry& e : r->sounds) {
      if (e.reason != reason->name()) continue;
      ++messages;
      EXPECT_EQ(e.kind, SoundKind::kSpeech) << e.key;
    }
    if (reason->number() == igms::object::FAILURE_NONE) {
      EXPECT_EQ(messages, 0) << reason->name() << " is no failure";
    } else {
      EXPECT_EQ(messages, 1) << reason->name() << " needs exactly one message in the bank";
    }
  }
  for (const SoundEntry& e : r->sounds) {
    if (e.reason.empty()) continue;
    EXPECT_NE(reasons->FindValueByName(e.reason), nullptr)
        << e.key << ": reason '" << e.reason << "' is no FailureReason of igms/object.proto";
  }
}

TEST(AudioFile, MissingCorruptAndEmptyFilesAreErrors) {
  const std::filesystem::path dir = igms::testing::FreshTempDir("audiofile");
  EXPECT_NE(ReadAudioFile(dir / "none.wav").error().find("missing"), std::string::npos);
  std::ofstream(dir / "junk.wav") << "RIFF????WAVEjunk";
  Result<AudioClip> junk = ReadAudioFile(dir / "junk.wav");
  EXPECT_FALSE(junk.ok());
  EXPECT_NE(junk.error().find("not a readable sound file"), std::string::npos) << junk.error();
  { std::ofstream empty(dir / "empty.wav"); }  // a file of no bytes
  EXPECT_FALSE(ReadAudioFile(dir / "empty.wav").ok());
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
  Result<Manifest> m = LoadManifest(dir / "manifest.yaml");
  ASSERT_TRUE(m.ok()) << m.error();
  const GenerateResult result = GenerateBank(*m, dir / "out");
  EXPECT_EQ(result.generated, 2);
  ASSERT_EQ(result.errors.size(), 1u);
  EXPECT_NE(result.errors[0].find("sound 2 'broken'"), std::string::npos) << result.errors[0];
  EXPECT_FALSE(std::filesystem::exists(dir / "out/cues/broken.wav"));
  EXPECT_TRUE(std::filesystem::exists(dir / "out/manifest.yaml"));
  Result<AudioClip> beep = ReadAudioFile(dir / "out/cues/beep.wav");
  ASSERT_TRUE(beep.ok()) << beep.error();
  EXPECT_EQ(beep->sample_rate, 16000);
  EXPECT_NEAR(beep->Seconds(), 0.25, 0.001);
  // A sine normalised to -6 dBFS peaks at 0.5 and has an RMS of 0.5 / sqrt(2).
  EXPECT_NEAR(RmsLevel(beep->samples, 0, SIZE_MAX), 0.5 / std::sqrt(2.0), 0.01);
  Result<AudioClip> hello = ReadAudioFile(dir / "out/speech/hello.wav");
  ASSERT_TRUE(hello.ok()) << hello.error();
  EXPECT_GT(hello->Seconds(), 0.3);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace igms::sound
