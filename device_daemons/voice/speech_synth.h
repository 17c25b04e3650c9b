// Spoken test utterances from a speech synthesiser (espeak-ng, or flite for a second kind of
// synthetic voice), so the recogniser can be exercised and measured without a person or
// recorded audio (and a simulated Dragon can "hear" an injected command through the real
// recogniser).
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "device_daemons/voice/audio.h"

namespace igms::voice {

enum class Synthesizer {
  kEspeakNg,  // formant synthesis, many accents and variants
  kFlite,     // CMU flite: diphone and statistical voices built from recorded speakers
};
std::string_view SynthesizerName(Synthesizer synthesizer);  // "espeak-ng", "flite"

struct SpeechRequest {
  std::string text;  // what to say
  // espeak-ng: a voice, optionally with a variant, "en-gb+f3". flite: one of its built-in
  // 16 kHz voices, "slt", "awb", "rms", "kal16" (a name only: flite would fetch a URL).
  std::string voice = "en-us";
  int words_per_minute = 175;      // espeak-ng's -s, 80..450; flite's own pace counts as 175
  int pitch = 50;                  // espeak-ng's -p, 0..99 (flite keeps its voice's pitch)
  double leading_silence_s = 0.0;  // digital silence added before and after
  double trailing_silence_s = 0.0;
  Synthesizer synthesizer = Synthesizer::kEspeakNg;
  bool Check(std::string* error) const;
};

// Runs the synthesiser (found on PATH) into a private temporary file and returns the
// utterance as 16 kHz mono. An error when the request is invalid, the
// synthesiser is missing or fails. The text and voice are passed as arguments, never
// through a shell.
Result<Audio> Synthesize(const SpeechRequest& request);

}  // namespace igms::voice
