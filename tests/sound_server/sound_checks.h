// Checks of captured audio against the bank's source audio, shared by the sound tests.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "sound_server/audio_file.h"
#include "sound_server/wave_capture.h"

namespace igms::sound::testing {

inline constexpr double kSilence = 0.002;  // of full scale: quieter than any sound's onset

// The captured sound has the source's audible length (within 20 ms) and level (within 5%,
// after `gain`), and its shape (correlation over 0.98 where it lines up).
inline void ExpectSameSound(const std::vector<int16_t>& captured, const AudioClip& source,
                            double gain, const std::string& what) {
  auto [s0, s1] = AudibleSpan(source.samples, kSilence);
  auto [c0, c1] = AudibleSpan(captured, kSilence * gain);
  ASSERT_GT(c1, c0) << what << ": nothing audible was captured";
  const double rate = source.sample_rate;
  EXPECT_NEAR(double(c1 - c0) / rate, double(s1 - s0) / rate, 0.02) << what;
  const double source_rms = RmsLevel(source.samples, s0, s1) * gain;
  EXPECT_NEAR(RmsLevel(captured, c0, c1) / source_rms, 1.0, 0.05) << what;
  const Alignment a = AlignClip(captured, source.samples, int64_t(c0) - int64_t(s0) - 64,
                                int64_t(c0) - int64_t(s0) + 64, 8192);
  EXPECT_GT(a.correlation, 0.98) << what;
}

}  // namespace igms::sound::testing
