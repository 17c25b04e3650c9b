#include "device_daemons/voice/endpointer.h"

#include <cstddef>
#include <stdexcept>

#include "device_daemons/voice/audio.h"

namespace igms::voice {

bool EndpointerOptions::Check(std::string* error) const {
  auto fail = [&](const char* why) {
    if (error) *error = why;
    return false;
  };
  if (sample_rate < 1000) return fail("endpointer sample_rate must be >= 1000");
  if (start_frames < 1) return fail("endpointer start_frames must be >= 1");
  if (end_silence_ms < 10 || pre_roll_ms < 0) return fail("endpointer timings out of range");
  if (!(max_utterance_s > 0.1)) return fail("endpointer max_utterance_s must be > 0.1");
  return true;
}

Endpointer::Endpointer(EndpointerOptions options)
    : options_(options), frame_size_(static_cast<size_t>(options.sample_rate / 100)) {
  std::string error;
  if (!options_.Check(&error)) throw std::invalid_argument(error);
}

std::vector<std::vector<int16_t>> Endpointer::Feed(std::span<const int16_t> samples) {
  std::vector<std::vector<int16_t>> done;
  partial_.insert(partial_.end(), samples.begin(), samples.end());
  size_t used = 0;
  while (partial_.size() - used >= frame_size_) {
    Frame(std::span<const int16_t>(partial_).subspan(used, frame_size_), done);
    used += frame_size_;
  }
  partial_.erase(partial_.begin(), partial_.begin() + static_cast<std::ptrdiff_t>(used));
  return done;
}

std::vector<std::vector<int16_t>> Endpointer::Flush() {
  std::vector<std::vector<int16_t>> done;
  if (in_speech_) {
    current_.insert(current_.end(), partial_.begin(), partial_.end());
    done.push_back(std::move(current_));
  }
  current_.clear();
  partial_.clear();
  history_.clear();
  in_speech_ = discarding_ = false;
  loud_run_ = quiet_run_ = 0;
  return done;
}

void Endpointer::Frame(std::span<const int16_t> frame, std::vector<std::vector<int16_t>>& done) {
  const bool loud = RmsDbfs(frame) > options_.threshold_dbfs;
  if (discarding_) {
    quiet_run_ = loud ? 0 : quiet_run_ + 1;
    if (quiet_run_ * 10 >= options_.end_silence_ms) discarding_ = false;
    return;
  }
  if (!in_speech_) {
    history_.insert(history_.end(), frame.begin(), frame.end());
    // Keep the pre-roll plus the loud frames that may start the utterance.
    const size_t keep = static_cast<size_t>(options_.pre_roll_ms) * options_.sample_rate / 1000 +
                        options_.start_frames * frame_size_;
    if (history_.size() > keep) {
      history_.erase(history_.begin(), history_.end() - static_cast<std::ptrdiff_t>(keep));
    }
    loud_run_ = loud ? loud_run_ + 1 : 0;
    if (loud_run_ >= options_.start_frames) {
      in_speech_ = true;
      quiet_run_ = 0;
      current_ = std::move(history_);
      history_.clear();
    }
    return;
  }
  current_.insert(current_.end(), frame.begin(), frame.end());
  quiet_run_ = loud ? 0 : quiet_run_ + 1;
  const bool ended = quiet_run_ * 10 >= options_.end_silence_ms;
  const bool too_long =
      current_.size() >= static_cast<size_t>(options_.max_utterance_s * options_.sample_rate);
  if (ended || too_long) {
    if (ended || !options_.discard_overlong) done.push_back(std::move(current_));
    discarding_ = !ended && options_.discard_overlong;
    current_.clear();
    in_speech_ = false;
    loud_run_ = 0;
  }
}

}  // namespace igms::voice
