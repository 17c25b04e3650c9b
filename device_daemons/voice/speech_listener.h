// SpeechListener: the modern stand-in for the Dragon speech PC inside igms-voiced. It
// decodes utterances with the Recognizer (recognizer.h) on its own thread and publishes
// each accepted command as the same VoiceState the Dragon's codes become (code, phrase,
// confidence, the state whose grammar accepted it; the stamp's device time is when the
// utterance ended, CLOCK_MONOTONIC in microseconds; the receive times are when its
// decoding finished).
//
// Utterances come from
//   - a microphone (OpenAL capture, cut by the Endpointer), when options.microphone,
//   - sound files, one every options.file_interval from the start, in order,
//   - Say(phrase): the phrase spoken by espeak-ng (the sim service's "spoken" input, so
//     tests and session scripts act as the operator through the real recogniser).
// Rejected utterances are not published; they are counted and the last reason is kept in
// the status message. SetState is the control client's word on the system's state: the
// grammar follows it from the next utterance, as it follows the recogniser's own
// prediction after an accepted command until then.
//
// Threading: everything public is thread-safe; on_reading runs on the listener's thread.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "device_daemons/voice/endpointer.h"
#include "device_daemons/voice/recognizer.h"
#include "igms/devices.pb.h"

namespace igms::voice {

struct SpeechListenerOptions {
  RecognizerOptions recognizer;
  bool microphone = false;
  std::string device;  // capture device; "" = the system's default
  EndpointerOptions endpointer;
  std::vector<std::string> files;
  std::chrono::milliseconds file_interval{1000};
  std::string voice = "en-us";  // espeak-ng voice for Say
  bool Check(std::string* error) const;
};

class SpeechListener {
 public:
  using ReadingFn = std::function<void(const devices::VoiceState&)>;

  // Loads the model, reads every file, opens the microphone and starts the thread. nullptr,
  // with *error set, when any of them fails.
  static std::unique_ptr<SpeechListener> Start(const SpeechListenerOptions& options,
                                               ReadingFn on_reading, std::string* error);
  ~SpeechListener();
  SpeechListener(const SpeechListener&) = delete;
  SpeechListener& operator=(const SpeechListener&) = delete;
  void Stop();

  void SetState(OperatorState state);
  // What the recogniser made of a phrase given to Say.
  using HeardFn = std::function<void(const devices::SimHeard&)>;
  // Queues a phrase to be spoken and heard. False, with *error set, for an empty or
  // overlong phrase or when too many are waiting. `heard`, when given, is called once on the
  // listener's thread when the phrase has been decoded (after any VoiceState it gave was
  // published), or when the listener stops first.
  bool Say(const std::string& phrase, std::string* error, HeardFn heard = nullptr);
  // Queues 16 kHz mono audio as one utterance.
  void Hear(std::vector<int16_t> samples);

  // CONNECTED while listening (REOPENING while the microphone is being reopened); port
  // names the input; readings, and a message with the state and the rejections.
  devices::LinkStatus status() const;
  uint64_t accepted() const { return accepted_; }
  uint64_t rejected() const { return rejected_; }

 private:
  struct Utterance {
    std::vector<int16_t> samples;
    std::string say;  // when not empty, synthesise this first
    std::string source;
    HeardFn heard;  // Say's caller, told what was heard
  };
  SpeechListener(SpeechListenerOptions options, ReadingFn on_reading);
  void Run();
  void Decode(Utterance utterance);
  void ListenToMicrophone();

  SpeechListenerOptions options_;
  ReadingFn on_reading_;
  std::unique_ptr<Recognizer> recognizer_;
  std::vector<std::vector<int16_t>> file_audio_;
  std::unique_ptr<class Microphone> microphone_;
  std::optional<Endpointer> endpointer_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Utterance> queue_;
  std::optional<OperatorState> requested_state_;
  OperatorState state_ = OperatorState::kVerification;
  std::string last_rejection_;
  bool microphone_failed_ = false;
  std::chrono::steady_clock::time_point retry_at_;  // next attempt to reopen the microphone
  uint64_t sequence_ = 0;
  std::atomic<uint64_t> accepted_{0}, rejected_{0};
};

}  // namespace igms::voice
