#include "device_daemons/voice/audio.h"

#include <sndfile.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace igms::voice {

Result<Audio> LoadSoundFile(const std::string& path, int target_rate) {
  auto fail = [&](const std::string& why) -> Result<Audio> {
    return ErrorMessage{path + ": " + why};
  };
  SF_INFO info{};
  SNDFILE* file = sf_open(path.c_str(), SFM_READ, &info);
  if (file == nullptr) return fail(sf_strerror(nullptr));
  if (info.channels < 1 || info.frames <= 0) {
    sf_close(file);
    return fail("holds no samples");
  }
  if (info.samplerate < 1000 || info.samplerate > 384000) {
    sf_close(file);
    return fail("unsupported sample rate " + std::to_string(info.samplerate));
  }
  // Read as float so mixing channels cannot overflow.
  std::vector<float> interleaved(static_cast<size_t>(info.frames) * info.channels);
  const sf_count_t got = sf_readf_float(file, interleaved.data(), info.frames);
  sf_close(file);
  if (got <= 0) return fail("could not read samples");
  std::vector<int16_t> mono(static_cast<size_t>(got));
  for (sf_count_t i = 0; i < got; ++i) {
    float sum = 0.0f;
    for (int c = 0; c < info.channels; ++c) sum += interleaved[i * info.channels + c];
    const float v = std::clamp(sum / static_cast<float>(info.channels), -1.0f, 1.0f) * 32767.0f;
    mono[i] = static_cast<int16_t>(std::lround(v));
  }
  Audio audio;
  audio.sample_rate = target_rate;
  audio.samples = Resample(mono, info.samplerate, target_rate);
  return audio;
}

std::vector<int16_t> Resample(std::span<const int16_t> samples, int from_rate, int to_rate) {
  if (from_rate <= 0 || to_rate <= 0) throw std::invalid_argument("Resample: rates must be > 0");
  if (from_rate == to_rate) return {samples.begin(), samples.end()};
  if (samples.empty()) return {};
  const double ratio = static_cast<double>(to_rate) / from_rate;
  // Cut-off as a fraction of the input rate, below both Nyquist frequencies.
  const double cutoff = 0.45 * std::min(1.0, ratio) * 2.0;  // in units of input Nyquist
  const int half_taps = 16;
  const double half_width = half_taps / std::min(1.0, ratio);  // in input samples
  const size_t out_size =
      static_cast<size_t>(std::floor(static_cast<double>(samples.size()) * ratio));
  std::vector<int16_t> out(out_size);
  for (size_t n = 0; n < out_size; ++n) {
    const double centre = static_cast<double>(n) / ratio;
    const long first = static_cast<long>(std::ceil(centre - half_width));
    const long last = static_cast<long>(std::floor(centre + half_width));
    double acc = 0.0;
    const long end = static_cast<long>(samples.size()) - 1;
    for (long k = std::max(0L, first); k <= std::min(last, end); ++k) {
      const double x = static_cast<double>(k) - centre;
      const double sinc =
          x == 0.0 ? 1.0 : std::sin(std::numbers::pi * cutoff * x) / (std::numbers::pi * x);
      const double window = 0.5 + 0.5 * std::cos(std::numbers::pi * x / half_width);  // Hann
      acc += samples[k] * (x == 0.0 ? cutoff : sinc) * window;
    }
    out[n] = static_cast<int16_t>(std::clamp(std::lround(acc), -32768L, 32767L));
  }
  return out;
}

double RmsDbfs(std::span<const int16_t> samples) {
  if (samples.empty()) return -std::numeric_limits<double>::infinity();
  double sum = 0.0;
  for (int16_t s : samples) sum += static_cast<double>(s) * s;
  const double rms = std::sqrt(sum / static_cast<double>(samples.size())) / 32768.0;
  return rms > 0.0 ? 20.0 * std::log10(rms) : -std::numeric_limits<double>::infinity();
}

}  // namespace igms::voice
