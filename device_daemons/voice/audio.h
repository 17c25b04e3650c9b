// Audio for the recogniser: 16-bit mono samples at the acoustic model's rate.
//
// The en-us model wants 16 kHz mono. WAV files of any rate and channel count (anything
// libsndfile reads) are mixed down to mono and resampled; a live stream arrives already
// at 16 kHz (see capture.h).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/base/result.h"

namespace igms::voice {

inline constexpr int kModelSampleRate = 16000;

struct Audio {
  std::vector<int16_t> samples;  // mono
  int sample_rate = kModelSampleRate;
  double seconds() const {
    return sample_rate > 0 ? static_cast<double>(samples.size()) / sample_rate : 0.0;
  }
};

// Reads a sound file and returns it as mono at `target_rate` Hz. An error when the file is
// missing, unreadable, empty or has a rate outside 1 kHz..384 kHz.
Result<Audio> LoadSoundFile(const std::string& path, int target_rate = kModelSampleRate);

// Band-limited resampling (windowed sinc, cut off at 0.45 of the lower rate). Returns the
// input unchanged when the rates are equal; an empty vector for empty input. Rates must be
// positive (a programmer error otherwise: std::invalid_argument).
std::vector<int16_t> Resample(std::span<const int16_t> samples, int from_rate, int to_rate);

// Root-mean-square level in dB relative to full scale (-inf dBFS for silence or nothing).
double RmsDbfs(std::span<const int16_t> samples);

}  // namespace igms::voice
