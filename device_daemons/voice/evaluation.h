// Measuring the recogniser on synthetic speech: recognition and false-accept rates and
// decode time, over a corpus of espeak-ng utterances.
//
// An in-vocabulary utterance counts as recognised when it is accepted as the command that
// was said, decoded in a state where that command is valid. An out-of-vocabulary one
// (any other word or phrase) counts as a false accept when anything is accepted, decoded in
// the model-building state (the largest vocabulary) unless the item names another state.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "device_daemons/voice/adaptation.h"
#include "device_daemons/voice/recognizer.h"
#include "device_daemons/voice/speech_synth.h"

namespace igms::voice {

struct Voice {
  std::string name;  // espeak-ng voice with variant, "en-gb+f3", or a flite voice, "slt"
  int words_per_minute = 175;
  Synthesizer synthesizer = Synthesizer::kEspeakNg;
  SpeechRequest Say(const std::string& text) const {
    SpeechRequest request{text, name, words_per_minute};
    request.synthesizer = synthesizer;
    return request;
  }
};

struct CorpusItem {
  SpeechRequest speech;
  std::optional<Command> expected;  // nullopt: must be rejected
  OperatorState state = OperatorState::kModelBuilding;
};

// The tuning set: the voices, speeds and other words the recogniser's settings are chosen
// on. The test set: voices (accent and variant) and speeds not in the tuning set, and other
// words not in its list; measured, never tuned on (docs/voice.md). The flite test voices are
// a second synthesiser's, never used for tuning or adaptation: speech unlike espeak-ng's.
const std::vector<Voice>& TuningVoices();
const std::vector<std::string>& TuningWords();
const std::vector<Voice>& TestVoices();
const std::vector<std::string>& TestWords();
const std::vector<Voice>& FliteTestVoices();

// `options` with every word of the tuning and test lists kept out of the filler words
// (grammar.h), so that a measurement counts only words the recogniser was never given.
// Every figure in docs/voice.md with filler words is measured this way.
RecognizerOptions WithoutEvaluationWords(RecognizerOptions options);

// Every command in every voice (in the first state where it is valid), then every
// out-of-vocabulary word in the voices taken in turn, `oov_voices_per_word` of them each.
std::vector<CorpusItem> BuildCorpus(const std::vector<Voice>& voices,
                                    const std::vector<std::string>& out_of_vocabulary,
                                    int oov_voices_per_word);

struct ItemResult {
  CorpusItem item;
  Recognition recognition;
  bool correct = false;  // recognised as expected, or rejected when it should be
};

struct EvaluationReport {
  int commands = 0, recognised = 0;
  int out_of_vocabulary = 0, false_accepts = 0;
  std::vector<double> decode_ms;  // one per utterance
  std::vector<ItemResult> results;
  double recognition_rate() const { return commands ? double(recognised) / commands : 0.0; }
  double false_accept_rate() const {
    return out_of_vocabulary ? double(false_accepts) / out_of_vocabulary : 0.0;
  }
  double decode_ms_quantile(double q) const;  // q in [0, 1]; 0 when empty
  std::string Summary() const;                // a few lines for a person
  std::string Failures() const;               // one line per wrong result
  std::string All() const;                    // one line per result
  // One comma-separated line per result, with a header: the features the recogniser
  // decides on, for choosing its settings outside the program.
  std::string Csv() const;
  // Recognition and false-accept rates had min_confidence been each of `thresholds`
  // (meaningful for thresholds at or above the one the corpus was decoded with), one line
  // each: how the confidence trades misses against false accepts.
  std::string Sweep(const std::vector<double>& thresholds) const;
  // Adds another report's utterances and counts to this one.
  void Append(const EvaluationReport& other);

 private:
  std::string Lines(bool all) const;
};

// Synthesises and decodes every item; the recogniser's state is set before each item and
// its own prediction does not carry over. An error when espeak-ng fails.
Result<EvaluationReport> Evaluate(Recognizer& recognizer, const std::vector<CorpusItem>& corpus);

// Synthetic enrolment: every prompt (by default the enrolment prompts, adaptation.h) said in
// each of `voices`, for adapting the model to espeak-ng's speech as an operator's enrolment
// adapts it to theirs. An error when espeak-ng fails.
Result<std::vector<AdaptationUtterance>> SynthesizeEnrolment(
    const std::vector<Voice>& voices, const std::vector<std::string>& prompts = EnrolmentPrompts());

// Each voice as an enrolled operator: the enrolment prompts said in that voice at
// `enrolment_wpm` adapt options.model_dir (AdaptModel, into a folder under `work_dir`), then
// that voice's commands and out-of-vocabulary words (BuildCorpus with every word) are
// decoded with `options` and the adapted model in place of options.model_dir. One report
// for all the voices; an error when synthesis, adaptation or the recogniser fails.
Result<EvaluationReport> EvaluateEnrolled(const std::vector<Voice>& voices,
                                          const std::vector<std::string>& out_of_vocabulary,
                                          int enrolment_wpm, const RecognizerOptions& options,
                                          const std::string& work_dir);

}  // namespace igms::voice
