// Recognition and false-accept rates on the test sets (evaluation.h): speech in voices and
// speeds that were not used to tune the recogniser, and words that were not in the tuning
// list, every word said in every voice. Two synthesisers: espeak-ng (the tuning set's) and
// flite (never tuned on). Prints the figures; asserts floors that guard against regressions
// (the targets, >= 95% and <= 5%, are printed beside them).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <optional>

#include "device_daemons/voice/evaluation.h"

namespace igms::voice {
namespace {

std::string TempFolder(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("igms_rates_" + name + "_" + std::to_string(getpid())))
      .string();
}

void CheckCounts(const EvaluationReport& report, size_t voices) {
  std::cout << report.Summary() << "wrong results:\n" << report.Failures();
  EXPECT_EQ(report.commands, static_cast<int>(11 * voices));
  EXPECT_EQ(report.out_of_vocabulary, static_cast<int>(TestWords().size() * voices));
}

std::optional<EvaluationReport> Measure(const RecognizerOptions& options,
                                        const std::vector<Voice>& voices) {
  std::string error;
  auto recognizer = Recognizer::Create(options, &error);
  EXPECT_NE(recognizer, nullptr) << error;
  if (!recognizer) return std::nullopt;
  const int every = static_cast<int>(voices.size());
  auto report = Evaluate(*recognizer, BuildCorpus(voices, TestWords(), every));
  EXPECT_TRUE(report.ok()) << report.error();
  if (!report.ok()) return std::nullopt;
  CheckCounts(*report, voices.size());
  return std::move(*report);
}

// Decoding is deterministic (fixed dither seed, fixed order), so a change in a figure below
// means a change in the recogniser. Each guard sits a little beyond the figure measured
// when it was written (docs/voice.md); where a guard is looser than the target, the target
// is missed.

TEST(VoiceRates, CommandsAndOutOfVocabularyOnUnseenVoices) {
  ASSERT_GE(TestWords().size(), 50u);
  const auto report = Measure(RecognizerOptions{}, TestVoices());
  ASSERT_TRUE(report);
  EXPECT_GE(report->recognition_rate(), 0.88);
  EXPECT_LE(report->false_accept_rate(), 0.16);
}

// A second synthesiser, never used for tuning: how far the espeak-ng-tuned settings carry to
// speech of another kind.
TEST(VoiceRates, CommandsAndOutOfVocabularyOnFliteVoices) {
  const auto report = Measure(RecognizerOptions{}, FliteTestVoices());
  ASSERT_TRUE(report);
  EXPECT_GE(report->recognition_rate(), 0.77);
  EXPECT_LE(report->false_accept_rate(), 0.17);
}

// The decoys chosen on the tuning set (without the playback-speed test): 15 per command at
// weight 1e-15 and min_confidence 0.1. The guards also fail if the grammar's decoy weight
// stops being applied (on the tuning set, the same decoys at weight 1 recognised 63.6% of
// the commands instead of 81.8%).
TEST(VoiceRates, WeightedDecoysOnUnseenVoices) {
  RecognizerOptions options;
  options.min_agreement = 0;
  options.decoys.max_per_command = 15;
  options.grammar.decoy_weight = 1e-15;
  options.min_confidence = 0.1;
  const auto report = Measure(options, TestVoices());
  ASSERT_TRUE(report);
  EXPECT_GE(report->recognition_rate(), 0.75);
  EXPECT_LE(report->false_accept_rate(), 0.18);
}

// Each test voice as an enrolled operator: the model adapted to that voice's own enrolment
// prompts, read at 175 words a minute (none of the test speeds), then that voice's commands
// and other words, decoded with the settings for an adapted model.
TEST(VoiceRates, EnrolledOperators) {
  const std::string work = TempFolder("enrolled");
  for (const auto* voices : {&TestVoices(), &FliteTestVoices()}) {
    const auto report = EvaluateEnrolled(
        *voices, TestWords(), 175,
        WithoutEvaluationWords(EnrolledRecognizerOptions(RecognizerOptions{}.model_dir)), work);
    ASSERT_TRUE(report.ok()) << report.error();
    CheckCounts(*report, voices->size());
    // Measured 97.7% and 2.9% (espeak-ng), 97.7% and 1.9% (flite): both targets met, and
    // the guards are the targets. Before the common-word check (step 6): 100.0% and 8.2%,
    // 93.2% and 3.8%.
    EXPECT_GE(report->recognition_rate(), 0.95);
    EXPECT_LE(report->false_accept_rate(), 0.05);
  }
  std::filesystem::remove_all(work);
}

}  // namespace
}  // namespace igms::voice
