// Prints the recogniser's figures: recognition and false-accept rates and decode time per
// utterance, on the voices used for tuning and on unseen ones, with the decode time of the
// bare grammar search (no confidence pass) in the same run as the baseline.
//   build/bench/bench_voice
#include <cstdlib>
#include <iostream>

#include "device_daemons/voice/evaluation.h"

using namespace igms::voice;

namespace {

const std::vector<std::string> kTuningWords = {
    "hello",  "table",   "breeze",    "rang",   "blocks", "cinder",   "market", "remark", "seven",
    "remote", "freezer", "ranger",    "marked", "boxes",  "solitude", "wire",   "frame",  "points",
    "model",  "remove",  "cylinders", "stop",   "go",     "yes",      "no"};

const std::vector<std::string> kTestWords = {
    "frees",     "fries",      "freed",          "three",    "cheese",    "strange", "change",
    "arrange",   "rain",       "refreeze",       "park",     "dark",      "marker",  "marking",
    "unpack",    "fox",        "socks",          "calendar", "slender",   "salad",   "valid",
    "fireman",   "removal",    "pointer",        "modeling", "computer",  "camera",  "video",
    "joystick",  "banana",     "elephant",       "window",   "seventeen", "eleven",  "forty",
    "green",     "orange",     "water",          "coffee",   "morning",   "station", "robot",
    "system",    "again",      "okay",           "maybe",    "never",     "ready",   "finish",
    "thank you", "good night", "what time is it"};

bool Run(const char* title, const RecognizerOptions& options, const std::vector<Voice>& voices,
         const std::vector<std::string>& words, bool sweep = false) {
  std::string error;
  auto recognizer = Recognizer::Create(options, &error);
  if (!recognizer) {
    std::cerr << error << "\n";
    return false;
  }
  const auto report = Evaluate(*recognizer, BuildCorpus(voices, words, 1), &error);
  if (!report) {
    std::cerr << error << "\n";
    return false;
  }
  std::cout << "== " << title << "\n" << report->Summary();
  if (sweep) std::cout << report->Sweep({0.01, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8});
  if (std::getenv("BENCH_VOICE_ALL")) std::cout << report->All();
  return true;
}

}  // namespace

int main() {
  const std::vector<Voice> tuning = {
      {"en-us", 140}, {"en-us", 190}, {"en-gb+f3", 140}, {"en-gb+f3", 190}};
  const std::vector<Voice> unseen = {{"en-gb-scotland+m3", 160},
                                     {"en-029+f2", 210},
                                     {"en-us-nyc+m4", 150},
                                     {"en-gb-x-rp+f4", 200}};
  RecognizerOptions options;
  RecognizerOptions grammar_only;  // accepts whatever the grammar decodes: no confidence
  grammar_only.min_confidence = 0.0;
  grammar_only.max_uncovered_speech_ms = 1e9;
  bool ok = Run("tuning voices and words", options, tuning, kTuningWords);
  ok &= Run("unseen voices and words", options, unseen, kTestWords);
  ok &= Run("unseen, grammar alone (min_confidence 0)", grammar_only, unseen, kTestWords);
  RecognizerOptions sweep = options;
  sweep.min_confidence = 1e-6;  // confidence computed, nearly everything accepted
  ok &= Run("tuning set, threshold sweep", sweep, tuning, kTuningWords, true);
  ok &= Run("unseen set, threshold sweep", sweep, unseen, kTestWords, true);
  return ok ? 0 : 1;
}
