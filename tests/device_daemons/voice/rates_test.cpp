// Recognition and false-accept rates on the test set (evaluation.h): espeak-ng speech in
// voices and speeds that were not used to tune the recogniser, and words that were not in
// the tuning list. Prints the figures; asserts floors that
// guard against regressions (the targets, >= 95% and <= 5%, are printed beside them).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <optional>

#include "device_daemons/voice/evaluation.h"

namespace igms::voice {
namespace {

std::optional<EvaluationReport> Measure(const RecognizerOptions& options) {
  std::string error;
  auto recognizer = Recognizer::Create(options, &error);
  EXPECT_NE(recognizer, nullptr) << error;
  if (!recognizer) return std::nullopt;
  auto report = Evaluate(*recognizer, BuildCorpus(TestVoices(), TestWords(), 1), &error);
  EXPECT_TRUE(report) << error;
  if (!report) return std::nullopt;
  std::cout << report->Summary() << "wrong results:\n" << report->Failures();
  EXPECT_EQ(report->commands, 11 * static_cast<int>(TestVoices().size()));
  EXPECT_EQ(report->out_of_vocabulary, static_cast<int>(TestWords().size()));
  return report;
}

TEST(VoiceRates, CommandsAndOutOfVocabularyOnUnseenVoices) {
  ASSERT_GE(TestWords().size(), 50u);
  const auto report = Measure(RecognizerOptions{});
  ASSERT_TRUE(report);
  // Regression guards a little below the measured 93.2% and above the measured 7.7%
  // (docs/voice.md): the unadapted model misses both targets. Decoding is deterministic (fixed dither
  // seed, fixed order), so a change in these figures means a change in the recogniser.
  EXPECT_GE(report->recognition_rate(), 0.86);
  EXPECT_LE(report->false_accept_rate(), 0.12);
}

// The decoys chosen on the tuning set (without the playback-speed test): 15 per command at
// weight 1e-15 and min_confidence 0.1. Measured 84.1% and 13.5% here (docs/voice.md). The
// guards also fail if the grammar's decoy weight stops being applied (on the tuning set, the
// same decoys at weight 1 recognised 63.6% of the commands instead of 81.8%).
TEST(VoiceRates, WeightedDecoysOnUnseenVoices) {
  RecognizerOptions options;
  options.min_agreement = 0;
  options.decoys.max_per_command = 15;
  options.grammar.decoy_weight = 1e-15;
  options.min_confidence = 0.1;
  const auto report = Measure(options);
  ASSERT_TRUE(report);
  EXPECT_GE(report->recognition_rate(), 0.75);
  EXPECT_LE(report->false_accept_rate(), 0.14);
}

// The model adapted to espeak-ng's speech as an operator's enrolment adapts it to theirs:
// every enrolment prompt in the twelve tuning voices (none of the test voices), then the test
// set. Measured 97.7% and 5.8% (docs/voice.md).
TEST(VoiceRates, AdaptedToTheTuningVoicesOnUnseenVoices) {
  std::string error;
  const auto enrolment = SynthesizeEnrolment(TuningVoices(), &error);
  ASSERT_TRUE(enrolment) << error;
  AdaptationOptions adaptation;
  adaptation.out_dir =
      (std::filesystem::temp_directory_path() / ("igms_rates_" + std::to_string(getpid())))
          .string();
  const AdaptationReport adapted = AdaptModel(*enrolment, adaptation);
  ASSERT_TRUE(adapted.ok()) << adapted.error;
  RecognizerOptions options;
  options.model_dir = adaptation.out_dir;
  const auto report = Measure(options);
  std::filesystem::remove_all(adaptation.out_dir);
  ASSERT_TRUE(report);
  EXPECT_GE(report->recognition_rate(), 0.93);
  EXPECT_LE(report->false_accept_rate(), 0.08);
}

}  // namespace
}  // namespace igms::voice
