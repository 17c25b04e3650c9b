// Recognition and false-accept rates on the test set (evaluation.h): espeak-ng speech in
// voices and speeds that were not used to tune the recogniser, and words that were not in
// the tuning list. Prints the figures; asserts floors that
// guard against regressions (the targets, >= 95% and <= 5%, are printed beside them).
#include <gtest/gtest.h>

#include <iostream>

#include "device_daemons/voice/evaluation.h"

namespace igms::voice {
namespace {

TEST(VoiceRates, CommandsAndOutOfVocabularyOnUnseenVoices) {
  ASSERT_GE(TestWords().size(), 50u);
  std::string error;
  auto recognizer = Recognizer::Create(RecognizerOptions{}, &error);
  ASSERT_NE(recognizer, nullptr) << error;
  const auto corpus = BuildCorpus(TestVoices(), TestWords(), 1);
  const auto report = Evaluate(*recognizer, corpus, &error);
  ASSERT_TRUE(report) << error;
  std::cout << report->Summary() << "wrong results:\n" << report->Failures();
  EXPECT_EQ(report->commands, 11 * static_cast<int>(TestVoices().size()));
  EXPECT_EQ(report->out_of_vocabulary, static_cast<int>(TestWords().size()));
  // Regression guards a little below the measured 86.4% and above the measured 15.4%
  // (docs/voice.md); the targets are NOT met yet. Decoding is deterministic (fixed dither
  // seed, fixed order), so a change in these figures means a change in the recogniser.
  EXPECT_GE(report->recognition_rate(), 0.80);
  EXPECT_LE(report->false_accept_rate(), 0.20);
}

}  // namespace
}  // namespace igms::voice
