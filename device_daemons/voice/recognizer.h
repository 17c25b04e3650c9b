// The speech recogniser: one utterance of audio in, one command code or a rejection out.
//
// Stands in for the thesis's Dragon Writer (Cooke, section 2.1.6) with CMU pocketsphinx and
// its en-us acoustic model. Each operator state has its own grammar (grammar.h); the
// recogniser decodes with the grammar of the state it was last told (SetState) and accepts
// a result only when
//   1. the best path is exactly one command token (not a decoy, not phones),
//   2. that command is valid in the current state,
//   3. no more than max_uncovered_speech_ms of speech lies outside the command's frames
//      (the fillers around it swallowed the rest of a longer word), and
//   4. its confidence is at least min_confidence. The confidence compares the command's
//      acoustic score per frame with a free decoding of the same frames by a phone loop
//      (pocketsphinx's allphone search), squashed into [0, 1], and
//   5. the same audio played a little faster and slower (speed and pitch together) is
//      decoded as the same command often enough: a near miss ("rage", "marked") sits
//      between a command and nothing, and a small change tips it over, and
//   6. when filler words are configured, decoding the utterance once more against every
//      command and the most common English words still gives the command (grammar.h).
// Anything else is a Rejection with a reason a person can read.
//
// Threading: one Recognizer is not thread-safe; use one per thread. Creating one loads the
// model (about a second); decoding a 1 s utterance takes tens of milliseconds.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "device_daemons/voice/command_language.h"
#include "device_daemons/voice/grammar.h"

namespace igms::voice {

struct RecognizerOptions {
  // Folder holding the acoustic model folder "en-us" and "cmudict-en-us.dict".
  std::string model_dir = "/usr/share/pocketsphinx/model/en-us";
  // Accept a command only when its confidence is at least this. 0 skips the confidence
  // pass altogether (about half the decode time; confidence is then reported as 0).
  double min_confidence = 0.2;
  // Confidence is a logistic function of the command's acoustic score per frame minus a
  // free phone decoding's over the same frames: 1 / (1 + exp(-(d - offset) / scale)).
  // Tuned on espeak-ng voices en-us and en-gb+f3 at 140 and 190 words a minute.
  double score_offset = -20.0;
  double score_scale = 5.0;
  // The state the recogniser starts in, until the control client says otherwise.
  OperatorState initial_state = OperatorState::kVerification;
  // Step 5: playback speeds to decode the utterance again at, and how many of them must give
  // the same command. min_agreement 0 turns it off. Chosen on the tuning set (docs/voice.md).
  std::vector<double> perturbations = {0.85, 0.92, 1.08, 1.15};
  int min_agreement = 2;
  // After accepting a command, move to PredictNextState() until told otherwise.
  bool predict_state = true;
  // Reject a command when more than this much speech (10 ms frames within 35 dB of the
  // utterance's loudest) lies outside the command word's frames: "market" heard as "mark"
  // and silence. Tuned on the tuning voices.
  double max_uncovered_speech_ms = 100.0;
  double speech_floor_db = 35.0;  // "speech" for the above: within this of the loudest frame
  // More pocketsphinx arguments, in pairs ("-beam", "1e-40"); one the recogniser also sets
  // replaces the built-in value.
  std::vector<std::string> decoder_args;
  DecoyOptions decoys;
  FillerWordOptions fillers;
  GrammarOptions grammar;
  bool Check(std::string* error) const;
};

// The front end's settings the recogniser decodes with, as pocketsphinx arguments in pairs;
// adaptation computes its features with the same (adaptation.h).
const std::vector<std::string>& FrontEndArgs();

enum class RejectReason {
  kNone,               // accepted
  kNoSpeech,           // nothing decoded (silence, too short, or no path through the grammar)
  kOutOfVocabulary,    // best path is decoy words or phones
  kNotValidInState,    // a command, but not one of the current state's
  kLowConfidence,      // a valid command whose posterior is below min_confidence
  kUnexplainedSpeech,  // a valid command, but too much speech outside it
  kUnstable,           // a valid command, but not heard again at other playback speeds
  kOtherWord,          // a valid command, but a common English word fits the speech better
};
std::string_view RejectReasonName(RejectReason reason);

struct Recognition {
  bool accepted = false;
  std::optional<Command> command;  // set when accepted, and for kNotValidInState/kLowConfidence
  double confidence = 0.0;         // in [0, 1]; 0 when no command was decoded
  RejectReason reason = RejectReason::kNone;
  std::string message;     // why rejected, for a person; empty when accepted
  std::string hypothesis;  // the decoder's best path, tokens separated by spaces
  OperatorState state = OperatorState::kVerification;  // the grammar it was decoded with
  double score_per_frame = 0.0;  // command minus phone loop, pocketsphinx's scaled log units
  double audio_seconds = 0.0;
  double decode_ms = 0.0;  // wall time spent decoding
  // Speech (10 ms frames within 35 dB of the loudest) outside the command word's frames:
  // what the decoder had to explain as silence or noise.
  double uncovered_speech_ms = 0.0;
  // Length of the command word's frames; 0 unless the best path is one word.
  double command_ms = 0.0;
  // How many of the perturbed decodings gave the same command (step 5); -1 when not tried.
  int agreement = -1;
  // What the verification against common words heard (step 6); empty when not tried.
  std::string verification;
};

class Recognizer {
 public:
  // Loads the model and builds every state's grammar. nullptr, with *error set, when the
  // options are invalid or the model or dictionary cannot be loaded.
  static std::unique_ptr<Recognizer> Create(const RecognizerOptions& options, std::string* error);
  ~Recognizer();
  Recognizer(const Recognizer&) = delete;
  Recognizer& operator=(const Recognizer&) = delete;

  // The control client's word on the system's state; takes effect from the next utterance.
  void SetState(OperatorState state);
  OperatorState state() const;

  // Decodes one utterance of 16 kHz mono audio (a little silence either side helps).
  // Empty or all-silent audio is rejected with kNoSpeech.
  Recognition Recognize(std::span<const int16_t> samples);

  // The JSGF text used for a state, for documentation and tests.
  const std::string& GrammarText(OperatorState state) const;
  size_t decoy_count() const;
  // The verification grammar (step 6); empty without filler words.
  const std::string& VerificationGrammarText() const;
  size_t filler_count() const;

 private:
  struct Impl;
  explicit Recognizer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace igms::voice
