// Reading and analysing what the wave output (audio_output.h) wrote, for tests and
// benchmarks that check the sound server's real output.
//
// OpenAL Soft's wave writer fills in the WAV header's sizes only when the device closes;
// while it plays, the header says 0 and the file grows in real time. These functions read
// the samples after the header whatever the header's sizes say, so a capture can be read
// while it is still being written (up to the writer's stdio buffer, a few kB behind).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace igms::sound {

struct Capture {
  int sample_rate = 0;
  std::vector<int16_t> samples;  // mono, 16-bit
};

// Reads a 16-bit mono WAV capture, complete or still growing. nullopt when the file is
// missing, not a WAV, or not 16-bit mono.
std::optional<Capture> ReadCapture(const std::filesystem::path& path);

// Frames written so far (from the file's size), or -1 when the header is not there yet.
int64_t CapturedFrames(const std::filesystem::path& path);

// Where `clip` best lines up with `signal`: the offset o in [from, to) maximising the
// correlation of signal[o + i] with clip[i] over the clip's first `window` samples, and the
// normalised correlation there (1 = identical shape). Brute force: keep ranges modest.
struct Alignment {
  int64_t offset = -1;
  double correlation = 0.0;
};
Alignment AlignClip(const std::vector<int16_t>& signal, const std::vector<int16_t>& clip,
                    int64_t from, int64_t to, size_t window = 4096);

// Subtracts gain * clip placed at `offset` from `signal` (in doubles, returned).
std::vector<double> Subtract(const std::vector<double>& signal, const std::vector<int16_t>& clip,
                             int64_t offset, double gain = 1.0);

// RMS of doubles in 16-bit units over [begin, end), relative to full scale.
double RmsOf(const std::vector<double>& signal, size_t begin, size_t end);

}  // namespace igms::sound
