// Recognition and false-accept rates on espeak-ng speech in voices and speeds that were not
// used to tune the recogniser (tuning: en-us and en-gb+f3 at 140 and 190 words a minute),
// and on words that were not in the tuning list. Prints the figures; asserts floors that
// guard against regressions (the targets, >= 95% and <= 5%, are printed beside them).
#include <gtest/gtest.h>

#include <iostream>

#include "device_daemons/voice/evaluation.h"

namespace igms::voice {
namespace {

const std::vector<Voice> kTestVoices = {
    {"en-gb-scotland+m3", 160},
    {"en-029+f2", 210},
    {"en-us-nyc+m4", 150},
    {"en-gb-x-rp+f4", 200},
};

// 25 near misses (sound like a command) and 27 unrelated words and phrases.
const std::vector<std::string> kOutOfVocabulary = {
    "frees",    "fries",     "freed",     "three",    "cheese",    "strange",   "change",
    "arrange",  "rain",      "refreeze",  "park",     "dark",      "marker",    "marking",
    "unpack",   "fox",       "socks",     "calendar", "slender",   "salad",     "valid",
    "fireman",  "removal",   "pointer",   "modeling", "computer",  "camera",    "video",
    "joystick", "banana",    "elephant",  "window",   "seventeen", "eleven",    "forty",
    "green",    "orange",    "water",     "coffee",   "morning",   "station",   "robot",
    "system",   "again",     "okay",      "maybe",    "never",     "ready",     "finish",
    "thank you", "good night", "what time is it",
};

TEST(VoiceRates, CommandsAndOutOfVocabularyOnUnseenVoices) {
  ASSERT_GE(kOutOfVocabulary.size(), 50u);
  std::string error;
  auto recognizer = Recognizer::Create(RecognizerOptions{}, &error);
  ASSERT_NE(recognizer, nullptr) << error;
  const auto corpus = BuildCorpus(kTestVoices, kOutOfVocabulary, 1);
  const auto report = Evaluate(*recognizer, corpus, &error);
  ASSERT_TRUE(report) << error;
  std::cout << report->Summary() << "wrong results:\n" << report->Failures();
  EXPECT_EQ(report->commands, 11 * static_cast<int>(kTestVoices.size()));
  EXPECT_EQ(report->out_of_vocabulary, static_cast<int>(kOutOfVocabulary.size()));
  // Regression guards a little below the measured 86.4% and above the measured 15.4%
  // (docs/voice.md); the targets are NOT met yet. Decoding is deterministic (fixed dither
  // seed, fixed order), so a change in these figures means a change in the recogniser.
  EXPECT_GE(report->recognition_rate(), 0.80);
  EXPECT_LE(report->false_accept_rate(), 0.20);
}

}  // namespace
}  // namespace igms::voice
