// Decoding one sound file into memory with libsndfile.
//
// Any format libsndfile reads (WAV, FLAC, Ogg Vorbis, AIFF, ...) is accepted; the samples
// come back as 16-bit signed mono (several channels are averaged), at the file's own rate.
// A missing, unreadable, corrupt, empty or over-long file is an error with a message naming
// the file and libsndfile's reason; nothing here throws on bad data.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/base/result.h"

namespace igms::sound {

struct AudioClip {
  std::vector<int16_t> samples;  // mono
  int sample_rate = 0;           // Hz
  double Seconds() const {
    return sample_rate > 0 ? static_cast<double>(samples.size()) / sample_rate : 0.0;
  }
};

// Longest clip accepted, so a wrong file cannot fill memory.
inline constexpr double kMaxClipSeconds = 120.0;

// The clip, or what is wrong with the file (naming it).
Result<AudioClip> ReadAudioFile(const std::filesystem::path& path);

// Root-mean-square level of samples [begin, end) relative to full scale (0..1).
double RmsLevel(const std::vector<int16_t>& samples, size_t begin, size_t end);

// The first and one-past-last sample whose magnitude exceeds `threshold` (0..1 of full
// scale); {0, 0} when none does.
std::pair<size_t, size_t> AudibleSpan(const std::vector<int16_t>& samples, double threshold,
                                      size_t begin = 0, size_t end = SIZE_MAX);

}  // namespace igms::sound
