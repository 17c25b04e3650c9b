// Adapting the acoustic model to a speaker: the recogniser's enrolment.
//
// The Dragon Writer was trained to its operator's voice (Cooke, section 2.1.6). pocketsphinx's
// en-us model was trained on many speakers, none of them ours; a few minutes of the
// operator's speech, with what was said, move its Gaussians towards that voice. This is MAP
// adaptation (maximum a posteriori: each Gaussian's mean and variance, each senone's mixture
// weights, moved towards the operator's statistics in proportion to how much of that speech
// it explained), with the counts gathered by a forced Baum-Welch pass. Both are sphinxtrain's
// programs (`bw`, `map_adapt`, Debian's package sphinxtrain); the features are computed here by
// the recogniser's own front end, so training and decoding see the same numbers.
//
// The result is a model folder like pocketsphinx's (the "en-us" acoustic model, adapted, and
// links to the dictionary and language models it came with): pass it as the recogniser's
// model_dir (`igms-voiced --model-dir`, `igms-voice-decode --model-dir`).
#pragma once

#include <string>
#include <vector>

#include "device_daemons/voice/audio.h"
#include "device_daemons/voice/recognizer.h"

namespace igms::voice {

// What to read at enrolment: every command phrase, then sentences that together hold every
// phone of the model in several contexts.
const std::vector<std::string>& EnrolmentPrompts();

struct AdaptationUtterance {
  Audio audio;       // 16 kHz mono
  std::string text;  // what was said: words of the dictionary or command phrases
};

struct AdaptationOptions {
  std::string model_dir = "/usr/share/pocketsphinx/model/en-us";  // the model to adapt
  std::string out_dir;                                            // the adapted model folder
  std::string sphinxtrain_dir = "/usr/lib/sphinxtrain";           // holds bw and map_adapt
  // Intermediate files (features, counts, the tools' logs) go to a private temporary folder,
  // removed afterwards unless this is set: then they are kept here.
  std::string work_dir;
  bool Check(std::string* error) const;
};

struct AdaptationReport {
  int utterances = 0;
  double seconds = 0.0;  // of speech given
  std::string error;     // empty on success
  bool ok() const { return error.empty(); }
};

// Adapts options.model_dir to `utterances` and writes the result to options.out_dir (replaced
// only when everything succeeded). Fails, saying why, on fewer than 10 utterances, a word
// with no pronunciation, audio not at 16 kHz, a missing tool, or a tool that fails (naming
// its log).
AdaptationReport AdaptModel(const std::vector<AdaptationUtterance>& utterances,
                            const AdaptationOptions& options);

// The file AdaptModel writes into the adapted model's folder: where it came from, how much
// speech it heard. Its presence is what makes a folder an adapted model.
inline constexpr const char* kAdaptationRecord = "igms-adaptation.txt";
bool IsAdaptedModel(const std::string& model_dir);

// The recogniser's settings for an adapted model: the defaults, plus 15 decoys per command
// at weight 1e-10, each accepted command checked against the 10000 most common English words
// at weight 1e-2 (grammar.h), and min_confidence 0.01. Chosen on the tuning voices, each
// enrolled on its own prompts: 98.5% recognised and 4.2% false accepts, against 97.0% and
// 13.2% without the common words (min_confidence 0.05) and the defaults' 96.2% and 20.8%
// (docs/voice.md).
// A model that fits its speaker lets other words win only where the speech is theirs; on the
// stock model the common words took genuine commands too, so they stay off there.
RecognizerOptions EnrolledRecognizerOptions(const std::string& model_dir);
// The settings for `model_dir`: EnrolledRecognizerOptions for an adapted model, else the
// defaults.
RecognizerOptions RecognizerOptionsFor(const std::string& model_dir);

}  // namespace igms::voice
