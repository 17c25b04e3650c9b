#include "device_daemons/voice/speech_synth.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <set>
#include <sstream>
#include <vector>

#include "common/process/process.h"

namespace igms::voice {
namespace {

std::vector<std::string> SynthesizerCommand(const SpeechRequest& request, const std::string& wav) {
  if (request.synthesizer == Synthesizer::kFlite) {
    // flite has no words-a-minute setting; its duration stretch scales its own pace.
    std::ostringstream stretch;
    stretch << "duration_stretch=" << 175.0 / request.words_per_minute;
    return {"flite", "-voice",     request.voice, "--setf", stretch.str(),
            "-t",    request.text, "-o",          wav};
  }
  return {"espeak-ng",
          "-v",
          request.voice,
          "-s",
          std::to_string(request.words_per_minute),
          "-p",
          std::to_string(request.pitch),
          "-w",
          wav,
          "--",
          request.text};
}

// flite speaks an unknown voice's name in its default 8 kHz voice without a word, so the
// name is checked against its own list ("Voices available: kal awb ...") first.
bool FliteHasVoice(const std::string& voice, const std::string& scratch, std::string* error) {
  static std::mutex mutex;
  static std::set<std::string> known;  // voices already found: one listing each
  std::lock_guard<std::mutex> lock(mutex);
  if (known.count(voice)) return true;
  const std::string failure = RunProgram({"flite", "-lv"}, scratch);
  std::ifstream in(scratch);
  std::string listed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!failure.empty()) {
    if (error) *error = "flite failed to list its voices: " + failure;
    return false;
  }
  while (!listed.empty() && std::isspace(static_cast<unsigned char>(listed.back())))
    listed.pop_back();
  std::istringstream words(listed.substr(std::min(listed.find(':'), listed.size())));
  for (std::string w; words >> w;) {
    if (w == voice) {
      known.insert(voice);
      return true;
    }
  }
  if (error) *error = "flite failed: it has no voice '" + voice + "' (" + listed + ")";
  return false;
}

}  // namespace

std::string_view SynthesizerName(Synthesizer synthesizer) {
  return synthesizer == Synthesizer::kFlite ? "flite" : "espeak-ng";
}

bool SpeechRequest::Check(std::string* error) const {
  auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (text.empty()) return fail("speech text is empty");
  if (voice.empty() || voice.front() == '-') return fail("bad espeak-ng voice '" + voice + "'");
  if (synthesizer == Synthesizer::kFlite && !std::all_of(voice.begin(), voice.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
      })) {
    return fail("bad flite voice '" + voice + "' (a built-in voice's name)");
  }
  if (words_per_minute < 80 || words_per_minute > 450) return fail("speed must be 80..450 wpm");
  if (pitch < 0 || pitch > 99) return fail("pitch must be 0..99");
  if (leading_silence_s < 0 || trailing_silence_s < 0 || leading_silence_s > 10 ||
      trailing_silence_s > 10) {
    return fail("silence must be 0..10 s");
  }
  return true;
}

Result<Audio> Synthesize(const SpeechRequest& request) {
  std::string error;
  if (!request.Check(&error)) return ErrorMessage{error};
  std::string path = (std::filesystem::temp_directory_path() / "igms-speech-XXXXXX.wav").string();
  const int fd = mkstemps(path.data(), 4);
  if (fd < 0) {
    return ErrorMessage{"cannot create a temporary file for espeak-ng"};
  }
  close(fd);
  if (request.synthesizer == Synthesizer::kFlite && !FliteHasVoice(request.voice, path, &error)) {
    std::filesystem::remove(path);
    return ErrorMessage{error};
  }
  const std::string failure = RunProgram(SynthesizerCommand(request, path));
  Result<Audio> audio = ErrorMessage{std::string(SynthesizerName(request.synthesizer)) +
                                     " failed for voice " + request.voice + ": " + failure};
  if (failure.empty()) audio = LoadSoundFile(path);
  std::filesystem::remove(path);
  if (!audio.ok()) return audio;
  const auto lead = static_cast<size_t>(request.leading_silence_s * audio->sample_rate);
  const auto trail = static_cast<size_t>(request.trailing_silence_s * audio->sample_rate);
  audio->samples.insert(audio->samples.begin(), lead, 0);
  audio->samples.insert(audio->samples.end(), trail, 0);
  return audio;
}

}  // namespace igms::voice
