#include "sound_server/audio_file.h"

#include <sndfile.h>

#include <cmath>
#include <cstdlib>
#include <memory>

namespace igms::sound {
namespace {

struct SndfileCloser {
  void operator()(SNDFILE* file) const { sf_close(file); }
};

}  // namespace

Result<AudioClip> ReadAudioFile(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return ErrorMessage{name + ": file is missing"};
  SF_INFO info{};
  std::unique_ptr<SNDFILE, SndfileCloser> file(sf_open(name.c_str(), SFM_READ, &info));
  if (!file)
    return ErrorMessage{name + ": not a readable sound file (" + sf_strerror(nullptr) + ")"};
  if (info.channels < 1 || info.samplerate < 1000 || info.samplerate > 384000) {
    return ErrorMessage{name + ": unsupported channel count or sample rate"};
  }
  if (info.frames <= 0) return ErrorMessage{name + ": holds no audio"};
  if (info.frames > static_cast<sf_count_t>(kMaxClipSeconds * info.samplerate)) {
    return ErrorMessage{name + ": longer than the " + std::to_string(int(kMaxClipSeconds)) +
                        " s a sound may last"};
  }
  std::vector<int16_t> interleaved(static_cast<size_t>(info.frames) * info.channels);
  const sf_count_t read = sf_readf_short(file.get(), interleaved.data(), info.frames);
  if (read <= 0) {
    return ErrorMessage{name + ": cannot decode (" + sf_strerror(file.get()) + ")"};
  }
  AudioClip clip;
  clip.sample_rate = info.samplerate;
  clip.samples.resize(static_cast<size_t>(read));
  for (size_t frame = 0; frame < clip.samples.size(); ++frame) {
    int sum = 0;
    for (int c = 0; c < info.channels; ++c) sum += interleaved[frame * info.channels + c];
    clip.samples[frame] = static_cast<int16_t>(sum / info.channels);
  }
  return clip;
}

double RmsLevel(const std::vector<int16_t>& samples, size_t begin, size_t end) {
  end = std::min(end, samples.size());
  if (begin >= end) return 0.0;
  double sum = 0.0;
  for (size_t i = begin; i < end; ++i) sum += double(samples[i]) * samples[i];
  return std::sqrt(sum / double(end - begin)) / 32768.0;
}

std::pair<size_t, size_t> AudibleSpan(const std::vector<int16_t>& samples, double threshold,
                                      size_t begin, size_t end) {
  end = std::min(end, samples.size());
  const int limit = static_cast<int>(threshold * 32768.0);
  size_t first = end;
  for (size_t i = begin; i < end; ++i) {
    if (std::abs(int(samples[i])) > limit) {
      first = i;
      break;
    }
  }
  if (first == end) return {0, 0};
  size_t last = first;
  for (size_t i = end; i > first; --i) {
    if (std::abs(int(samples[i - 1])) > limit) {
      last = i;
      break;
    }
  }
  return {first, last};
}

}  // namespace igms::sound
