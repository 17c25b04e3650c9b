// Spoken test utterances from espeak-ng, so the recogniser can be exercised and measured
// without a person or recorded audio (and a simulated Dragon can "hear" an injected
// command through the real recogniser).
#pragma once

#include <optional>
#include <string>

#include "device_daemons/voice/audio.h"

namespace igms::voice {

struct SpeechRequest {
  std::string text;           // what to say
  std::string voice = "en-us";  // an espeak-ng voice, optionally with a variant: "en-gb+f3"
  int words_per_minute = 175;   // espeak-ng's -s, 80..450
  int pitch = 50;               // espeak-ng's -p, 0..99
  double leading_silence_s = 0.0;   // digital silence added before and after
  double trailing_silence_s = 0.0;
  bool Check(std::string* error) const;
};

// Runs espeak-ng (found on PATH) into a private temporary file and returns the utterance
// as 16 kHz mono. nullopt, with *error set, when the request is invalid, espeak-ng is
// missing or fails. The text and voice are passed as arguments, never through a shell.
std::optional<Audio> Synthesize(const SpeechRequest& request, std::string* error);

}  // namespace igms::voice
