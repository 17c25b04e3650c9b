// Cuts a continuous 16 kHz sample stream (a microphone) into utterances by energy.
//
// Pure: samples in, finished utterances out, no I/O, no clock. The stream is judged in
// 10 ms frames: speech starts after `start_frames` consecutive frames louder than
// `threshold_dbfs`, and ends after `end_silence_ms` of quieter frames. Each utterance keeps
// `pre_roll_ms` of audio before its start and the trailing silence, so word edges are not
// clipped. Speech longer than `max_utterance_s` is no command (commands last a second or
// two): it is dropped whole, up to its end of speech, unless `discard_overlong` is off, when
// it is cut there instead (and the rest starts a new utterance mid-word).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace igms::voice {

struct EndpointerOptions {
  double threshold_dbfs = -40.0;
  int start_frames = 3;
  int end_silence_ms = 400;
  int pre_roll_ms = 200;
  double max_utterance_s = 5.0;
  bool discard_overlong = true;
  int sample_rate = 16000;
  bool Check(std::string* error) const;
};

class Endpointer {
 public:
  explicit Endpointer(EndpointerOptions options = {});
  // Feeds samples; returns every utterance that ended inside them (usually none or one).
  std::vector<std::vector<int16_t>> Feed(std::span<const int16_t> samples);
  // Ends the stream: returns the utterance in progress, if any.
  std::vector<std::vector<int16_t>> Flush();
  bool in_speech() const { return in_speech_; }

 private:
  void Frame(std::span<const int16_t> frame, std::vector<std::vector<int16_t>>& done);

  EndpointerOptions options_;
  size_t frame_size_;
  std::vector<int16_t> partial_;  // samples not yet making a whole frame
  std::vector<int16_t> history_;  // recent frames before speech (pre-roll)
  std::vector<int16_t> current_;  // the utterance in progress
  bool in_speech_ = false;
  bool discarding_ = false;  // inside overlong speech, waiting for its end
  int loud_run_ = 0;
  int quiet_run_ = 0;
};

}  // namespace igms::voice
