#include "device_daemons/voice/speech_synth.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "common/process/process.h"

namespace igms::voice {

bool SpeechRequest::Check(std::string* error) const {
  auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (text.empty()) return fail("speech text is empty");
  if (voice.empty() || voice.front() == '-') return fail("bad espeak-ng voice '" + voice + "'");
  if (words_per_minute < 80 || words_per_minute > 450) return fail("speed must be 80..450 wpm");
  if (pitch < 0 || pitch > 99) return fail("pitch must be 0..99");
  if (leading_silence_s < 0 || trailing_silence_s < 0 || leading_silence_s > 10 ||
      trailing_silence_s > 10) {
    return fail("silence must be 0..10 s");
  }
  return true;
}

std::optional<Audio> Synthesize(const SpeechRequest& request, std::string* error) {
  if (!request.Check(error)) return std::nullopt;
  std::string path = (std::filesystem::temp_directory_path() / "igms-speech-XXXXXX.wav").string();
  const int fd = mkstemps(path.data(), 4);
  if (fd < 0) {
    if (error) *error = "cannot create a temporary file for espeak-ng";
    return std::nullopt;
  }
  close(fd);
  const std::string failure = RunProgram({"espeak-ng", "-v", request.voice, "-s",
                                           std::to_string(request.words_per_minute), "-p",
                                           std::to_string(request.pitch), "-w", path, "--",
                                           request.text});
  std::optional<Audio> audio;
  if (failure.empty()) {
    audio = LoadSoundFile(path, error);
  } else if (error) {
    *error = "espeak-ng failed for voice " + request.voice + ": " + failure;
  }
  std::filesystem::remove(path);
  if (!audio) return std::nullopt;
  const auto lead = static_cast<size_t>(request.leading_silence_s * audio->sample_rate);
  const auto trail = static_cast<size_t>(request.trailing_silence_s * audio->sample_rate);
  audio->samples.insert(audio->samples.begin(), lead, 0);
  audio->samples.insert(audio->samples.end(), trail, 0);
  return audio;
}

}  // namespace igms::voice
