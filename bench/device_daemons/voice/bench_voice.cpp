// Prints the recogniser's figures: recognition and false-accept rates and decode time per
// utterance, on the tuning set and on the held-out test sets (evaluation.h: espeak-ng's test
// voices and flite's, every other word in every voice), the test set with the grammar alone,
// confidence-threshold sweeps, and each test voice as an enrolled operator.
//   build/bench/bench_voice [tuning|test|flite|enrolled|enrolled-tuning|adapted|all]
// (default all; enrolled-tuning: each tuning voice enrolled on its own, with every tuning
// word; adapted: one model adapted to every tuning voice's enrolment prompts, on both test
// sets: what a model adapted to other speakers does; neither is in all)
// BENCH_VOICE_ALL=1 adds one line per utterance; BENCH_VOICE_GRAMMAR=1 prints the
// model-building state's grammar (with its decoys); BENCH_VOICE_CSV=prefix writes each set's
// features per utterance to prefix-<set>.csv (tune on the tuning set's only);
// BENCH_VOICE_NO_SWEEP=1 leaves out the sweeps and the grammar-alone run. Settings to try,
// applied to every run: BENCH_VOICE_ARGS="-beam 1e-30 ..." (pocketsphinx arguments),
// BENCH_VOICE_DECOYS=N (decoys per command), BENCH_VOICE_MIN_CONFIDENCE=C,
// BENCH_VOICE_MIN_AGREEMENT=K, BENCH_VOICE_PERTURBATIONS="0.9 1.1",
// BENCH_VOICE_MAX_UNCOVERED_MS=MS, BENCH_VOICE_MODEL_DIR=DIR (e.g. an adapted model from
// igms-voice-adapt, decoded with the settings for an adapted model unless the variables here
// say otherwise; the enrolled sets always start from those), BENCH_VOICE_TUNING_VOICES="0 2 5"
// (a subset of the tuning voices, by index, e.g. the half an adaptation was not made from),
// BENCH_VOICE_DECOY_WEIGHT=W and BENCH_VOICE_LOOP_WEIGHT=W (grammar weights; the loop is off
// at 0), BENCH_VOICE_DECOY_MIN_UNIGRAM=L and BENCH_VOICE_DECOY_DISTANCE=F (which dictionary
// words may be decoys: DecoyOptions), BENCH_VOICE_FILLERS=N, BENCH_VOICE_FILLER_WEIGHT=W,
// BENCH_VOICE_FILLER_MARGIN=K and BENCH_VOICE_FILLER_MIN_PHONES=P (the common words each
// accepted command is checked against: FillerWordOptions). Every tuning and test word is
// always left out of the common words, so a figure counts only words the check never saw.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "bench/bench_main.h"
#include "device_daemons/voice/evaluation.h"

using namespace igms::voice;

namespace {

bool Run(const std::string& title, const RecognizerOptions& options,
         const std::vector<Voice>& voices, const std::vector<std::string>& words, int per_word,
         bool sweep = false) {
  std::string error;
  auto recognizer = Recognizer::Create(options, &error);
  if (!recognizer) {
    std::cerr << error << "\n";
    return false;
  }
  if (std::getenv("BENCH_VOICE_GRAMMAR")) {
    std::cout << recognizer->GrammarText(OperatorState::kModelBuilding) << "\n";
    if (recognizer->filler_count() > 0)  // the first words of a long list
      std::cout << recognizer->VerificationGrammarText().substr(0, 2000) << " ... ("
                << recognizer->filler_count() << " common words)\n";
  }
  const auto report = Evaluate(*recognizer, BuildCorpus(voices, words, per_word));
  if (!report.ok()) {
    std::cerr << report.error() << "\n";
    return false;
  }
  std::cout << "== " << title << " (" << recognizer->decoy_count() << " decoys)\n"
            << report->Summary();
  if (sweep) std::cout << report->Sweep({0.01, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8});
  if (std::getenv("BENCH_VOICE_ALL")) std::cout << report->All();
  if (const char* prefix = std::getenv("BENCH_VOICE_CSV")) {
    std::string name = title.substr(0, title.find(' '));
    std::ofstream(std::string(prefix) + "-" + name + ".csv") << report->Csv();
  }
  return true;
}

struct EnrolledSet {
  const char* title;
  const std::vector<Voice>& voices;
  const std::vector<std::string>& words;
};

// Each voice enrolled on its own (175 wpm prompts), then measured on its commands and words.
bool RunEnrolled(const RecognizerOptions& options, const std::vector<EnrolledSet>& sets) {
  const std::string work =
      std::filesystem::temp_directory_path() / ("bench_voice_enrolled_" + std::to_string(getpid()));
  bool ok = true;
  for (const EnrolledSet& set : sets) {
    const auto report = EvaluateEnrolled(set.voices, set.words, 175, options, work);
    if (!report.ok()) {
      std::cerr << report.error() << "\n";
      ok = false;
      continue;
    }
    std::cout << "== " << set.title << "\n" << report->Summary();
    if (std::getenv("BENCH_VOICE_ALL")) std::cout << report->All();
  }
  std::filesystem::remove_all(work);
  return ok;
}

// Sets `field` from the environment variable `name` when it is set.
void FromEnvironment(const char* name, int& field) {
  if (const char* v = std::getenv(name)) field = std::atoi(v);
}
void FromEnvironment(const char* name, double& field) {
  if (const char* v = std::getenv(name)) field = std::atof(v);
}

// The settings to try, from the environment, over `options`.
RecognizerOptions WithEnvironment(RecognizerOptions options) {
  if (const char* extra = std::getenv("BENCH_VOICE_ARGS")) {
    std::istringstream in(extra);
    for (std::string a; in >> a;) options.decoder_args.push_back(a);
  }
  if (const char* list = std::getenv("BENCH_VOICE_PERTURBATIONS")) {
    std::istringstream in(list);
    options.perturbations.clear();
    for (double f; in >> f;) options.perturbations.push_back(f);
  }
  FromEnvironment("BENCH_VOICE_DECOYS", options.decoys.max_per_command);
  FromEnvironment("BENCH_VOICE_DECOY_MIN_UNIGRAM", options.decoys.min_log10_unigram);
  FromEnvironment("BENCH_VOICE_DECOY_DISTANCE", options.decoys.max_distance_fraction);
  FromEnvironment("BENCH_VOICE_DECOY_WEIGHT", options.grammar.decoy_weight);
  FromEnvironment("BENCH_VOICE_MIN_CONFIDENCE", options.min_confidence);
  FromEnvironment("BENCH_VOICE_MAX_UNCOVERED_MS", options.max_uncovered_speech_ms);
  FromEnvironment("BENCH_VOICE_MIN_AGREEMENT", options.min_agreement);
  FromEnvironment("BENCH_VOICE_FILLERS", options.fillers.count);
  FromEnvironment("BENCH_VOICE_FILLER_MIN_PHONES", options.fillers.min_phones);
  FromEnvironment("BENCH_VOICE_FILLER_MARGIN", options.fillers.margin);
  FromEnvironment("BENCH_VOICE_FILLER_WEIGHT", options.fillers.weight);
  FromEnvironment("BENCH_VOICE_LOOP_WEIGHT", options.grammar.phone_loop_weight);
  return WithoutEvaluationWords(options);
}

// One model adapted to every enrolment prompt of the twelve tuning voices (none of the test
// voices), then both test sets decoded with it, with the settings for an adapted model.
bool RunAdaptedToTuningVoices() {
  const auto enrolment = SynthesizeEnrolment(TuningVoices());
  if (!enrolment.ok()) {
    std::cerr << enrolment.error() << "\n";
    return false;
  }
  AdaptationOptions adaptation;
  adaptation.out_dir =
      std::filesystem::temp_directory_path() / ("bench_voice_adapted_" + std::to_string(getpid()));
  const AdaptationReport adapted = AdaptModel(*enrolment, adaptation);
  bool ok = adapted.ok() && IsAdaptedModel(adaptation.out_dir);
  if (!ok) std::cerr << "adaptation failed: " << adapted.error << "\n";
  if (ok) {
    const RecognizerOptions options = WithEnvironment(RecognizerOptionsFor(adaptation.out_dir));
    const int espeak = static_cast<int>(TestVoices().size());
    const int flite = static_cast<int>(FliteTestVoices().size());
    ok &= Run("adapted-espeak set, adapted to the tuning voices", options, TestVoices(),
              TestWords(), espeak);
    ok &= Run("adapted-flite set, adapted to the tuning voices", options, FliteTestVoices(),
              TestWords(), flite);
  }
  std::filesystem::remove_all(adaptation.out_dir);
  return ok;
}

int RunBenchmark(int argc, char** argv) {
  const std::string which = argc > 1 ? argv[1] : "all";
  if (which != "tuning" && which != "test" && which != "flite" && which != "enrolled" &&
      which != "enrolled-tuning" && which != "adapted" && which != "all") {
    std::cerr << "usage: bench_voice [tuning|test|flite|enrolled|enrolled-tuning|adapted|all]\n";
    return 2;
  }
  if (which == "adapted") return RunAdaptedToTuningVoices() ? 0 : 1;
  // An adapted model gets the settings igms-voiced gives it (adaptation.h).
  const char* dir = std::getenv("BENCH_VOICE_MODEL_DIR");
  const RecognizerOptions options =
      WithEnvironment(RecognizerOptionsFor(dir ? dir : RecognizerOptions{}.model_dir));
  RecognizerOptions grammar_only = options;  // accepts whatever the grammar decodes: no confidence
  grammar_only.min_confidence = 0.0;
  grammar_only.max_uncovered_speech_ms = 1e9;
  grammar_only.min_agreement = 0;
  RecognizerOptions sweep = options;
  sweep.min_confidence = 1e-6;  // confidence computed, nearly everything accepted
  const bool sweeps = std::getenv("BENCH_VOICE_NO_SWEEP") == nullptr;
  bool ok = true;
  // Each other word in two tuning voices: the tuning set is for choosing, so more is better.
  std::vector<Voice> tuning = TuningVoices();
  if (const char* list = std::getenv("BENCH_VOICE_TUNING_VOICES")) {
    std::istringstream in(list);
    tuning.clear();
    for (size_t i; in >> i;) {
      if (i < TuningVoices().size()) tuning.push_back(TuningVoices()[i]);
    }
  }
  const auto wanted = [&](const char* set) { return which == "all" || which == set; };
  if (wanted("tuning")) {
    ok &= Run("tuning voices and words", options, tuning, TuningWords(), 2);
    if (sweeps)
      ok &= Run("tuning-sweep set, threshold sweep", sweep, tuning, TuningWords(), 2, true);
  }
  const int every = static_cast<int>(TestVoices().size());  // every test word in every voice
  if (wanted("test")) {
    ok &= Run("test voices and words", options, TestVoices(), TestWords(), every);
    if (sweeps) {
      ok &= Run("test-grammar set, grammar alone (min_confidence 0)", grammar_only, TestVoices(),
                TestWords(), every);
      ok &= Run("test-sweep set, threshold sweep", sweep, TestVoices(), TestWords(), every, true);
    }
  }
  if (wanted("flite")) {
    ok &= Run("flite test voices and words", options, FliteTestVoices(), TestWords(),
              static_cast<int>(FliteTestVoices().size()));
  }
  const RecognizerOptions enrolled = WithEnvironment(EnrolledRecognizerOptions(options.model_dir));
  if (wanted("enrolled")) {
    ok &= RunEnrolled(enrolled, {{"enrolled espeak-ng test voices", TestVoices(), TestWords()},
                                 {"enrolled flite test voices", FliteTestVoices(), TestWords()}});
  }
  if (which == "enrolled-tuning")  // for choosing settings for enrolled operators
    ok &= RunEnrolled(enrolled, {{"enrolled tuning voices", tuning, TuningWords()}});
  return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  return igms::bench::MainReportingFailures(argc, argv, RunBenchmark);
}
