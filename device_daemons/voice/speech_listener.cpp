#include "device_daemons/voice/speech_listener.h"

#include <spdlog/spdlog.h>

#include "common/base/clock.h"
#include "device_daemons/voice/audio.h"
#include "device_daemons/voice/microphone.h"
#include "device_daemons/voice/speech_synth.h"
#include "device_daemons/voice/voice_proto.h"

namespace igms::voice {
namespace {

constexpr size_t kMaxQueued = 16;
constexpr size_t kMaxPhrase = 200;
constexpr auto kMicrophonePoll = std::chrono::milliseconds(20);
constexpr auto kMicrophoneRetry = std::chrono::seconds(1);

}  // namespace

bool SpeechListenerOptions::Check(std::string* error) const {
  if (!recognizer.Check(error) || !endpointer.Check(error)) return false;
  if (file_interval.count() < 0) {
    *error = "the interval between sound files must be >= 0";
    return false;
  }
  return true;
}

SpeechListener::SpeechListener(SpeechListenerOptions options, ReadingFn on_reading)
    : options_(std::move(options)), on_reading_(std::move(on_reading)) {}

std::unique_ptr<SpeechListener> SpeechListener::Start(const SpeechListenerOptions& options,
                                                      ReadingFn on_reading, std::string* error) {
  if (!options.Check(error)) return nullptr;
  std::unique_ptr<SpeechListener> l(new SpeechListener(options, std::move(on_reading)));
  for (const std::string& file : options.files) {
    auto audio = LoadSoundFile(file);
    if (!audio.ok()) {
      Fail(error, audio.error());
      return nullptr;
    }
    l->file_audio_.push_back(std::move(audio->samples));
  }
  // The microphone first: a missing one is reported at once, not after the model loads.
  if (options.microphone) {
    l->microphone_ = Microphone::Open(options.device, error);
    if (!l->microphone_) return nullptr;
    l->endpointer_.emplace(options.endpointer);
  }
  l->recognizer_ = Recognizer::Create(options.recognizer, error);
  if (!l->recognizer_) return nullptr;
  l->state_ = l->recognizer_->state();
  l->running_ = true;
  l->thread_ = std::thread([raw = l.get()] { raw->Run(); });
  return l;
}

SpeechListener::~SpeechListener() { Stop(); }

void SpeechListener::Stop() {
  {
    std::lock_guard lock(mutex_);
    running_ = false;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  std::deque<Utterance> left;
  {
    std::lock_guard lock(mutex_);
    left.swap(queue_);
  }
  for (Utterance& u : left) {
    if (!u.heard) continue;
    devices::SimHeard heard;
    heard.set_text(u.say);
    heard.set_detail("the recogniser stopped before hearing it");
    u.heard(heard);
  }
}

void SpeechListener::SetState(OperatorState state) {
  std::lock_guard lock(mutex_);
  requested_state_ = state;
  state_ = state;
}

bool SpeechListener::Say(const std::string& phrase, std::string* error, HeardFn heard) {
  if (phrase.empty() || phrase.size() > kMaxPhrase) {
    *error = "a spoken phrase must have 1 to " + std::to_string(kMaxPhrase) + " characters";
    return false;
  }
  {
    std::lock_guard lock(mutex_);
    if (queue_.size() >= kMaxQueued) {
      *error = "the recogniser is busy: " + std::to_string(queue_.size()) + " utterances waiting";
      return false;
    }
    queue_.push_back({{}, phrase, "spoken \"" + phrase + "\"", std::move(heard)});
  }
  wake_.notify_all();
  return true;
}

void SpeechListener::Hear(std::vector<int16_t> samples) {
  {
    std::lock_guard lock(mutex_);
    queue_.push_back({std::move(samples), {}, "audio", nullptr});
  }
  wake_.notify_all();
}

devices::LinkStatus SpeechListener::status() const {
  std::lock_guard lock(mutex_);
  devices::LinkStatus s;
  s.set_state(microphone_failed_ ? devices::REOPENING : devices::CONNECTED);
  s.set_port(options_.microphone
                 ? "microphone " + (options_.device.empty() ? "(default)" : options_.device)
                 : "recogniser");
  s.set_readings(accepted_);
  std::string message = "listening in state " + std::string(StateName(state_)) + "; " +
                        std::to_string(accepted_) + " accepted, " + std::to_string(rejected_) +
                        " rejected";
  if (!last_rejection_.empty()) message += "; last rejected: " + last_rejection_;
  s.set_message(message);
  return s;
}

void SpeechListener::Run() {
  size_t next_file = 0;
  auto file_due = std::chrono::steady_clock::now() + options_.file_interval;
  while (true) {
    std::optional<Utterance> utterance;
    {
      std::unique_lock lock(mutex_);
      auto deadline = std::chrono::steady_clock::now() +
                      (microphone_ ? std::chrono::milliseconds(kMicrophonePoll)
                                   : std::chrono::milliseconds(500));
      if (next_file < file_audio_.size()) deadline = std::min(deadline, file_due);
      wake_.wait_until(lock, deadline, [&] { return !running_ || !queue_.empty(); });
      if (!running_) return;
      if (!queue_.empty()) {
        utterance = std::move(queue_.front());
        queue_.pop_front();
      }
    }
    if (next_file < file_audio_.size() && std::chrono::steady_clock::now() >= file_due) {
      Decode({file_audio_[next_file], {}, options_.files[next_file], nullptr});
      ++next_file;
      file_due += options_.file_interval;
    }
    if (utterance) Decode(std::move(*utterance));
    if (microphone_ || microphone_failed_) ListenToMicrophone();
  }
}

void SpeechListener::ListenToMicrophone() {
  if (!microphone_) {
    if (std::chrono::steady_clock::now() < retry_at_) return;
    std::string error;
    microphone_ = Microphone::Open(options_.device, &error);
    if (!microphone_) {
      retry_at_ = std::chrono::steady_clock::now() + kMicrophoneRetry;
      return;
    }
    spdlog::info("voice: the microphone is back");
    std::lock_guard lock(mutex_);
    microphone_failed_ = false;
  }
  std::vector<int16_t> samples;
  if (!microphone_->Read(samples)) {
    spdlog::error("voice: the capture device stopped; reopening it every second");
    microphone_.reset();
    endpointer_.emplace(options_.endpointer);
    retry_at_ = std::chrono::steady_clock::now() + kMicrophoneRetry;
    std::lock_guard lock(mutex_);
    microphone_failed_ = true;
    return;
  }
  for (auto& u : endpointer_->Feed(samples)) Decode({std::move(u), {}, "microphone", nullptr});
}

void SpeechListener::Decode(Utterance u) {
  const int64_t heard_ns = igms::MonotonicNs();
  {
    std::lock_guard lock(mutex_);
    if (requested_state_) recognizer_->SetState(*requested_state_);
    requested_state_.reset();
  }
  if (!u.say.empty()) {
    SpeechRequest request;
    request.text = u.say;
    request.voice = options_.voice;
    auto audio = Synthesize(request);
    if (!audio.ok()) {
      const std::string& error = audio.error();
      spdlog::error("voice: cannot speak \"{}\": {}", u.say, error);
      {
        std::lock_guard lock(mutex_);
        ++rejected_;
        last_rejection_ = u.source + ": " + error;
      }
      if (u.heard) {
        devices::SimHeard heard;
        heard.set_text(u.say);
        heard.set_detail("cannot speak it: " + error);
        u.heard(heard);
      }
      return;
    }
    u.samples = std::move(audio->samples);
  }
  const Recognition r = recognizer_->Recognize(u.samples);
  // Say's caller learns what the recogniser heard, accepted or not.
  auto tell = [&] {
    if (!u.heard) return;
    devices::SimHeard heard;
    heard.set_accepted(r.accepted);
    if (r.command) heard.set_command(ToProto(*r.command));
    heard.set_text(r.hypothesis);
    heard.set_state(ToProto(r.state));
    heard.set_confidence(r.confidence);
    heard.set_detail(r.message);
    u.heard(heard);
  };
  devices::VoiceState reading;
  {
    std::lock_guard lock(mutex_);
    if (!requested_state_) state_ = recognizer_->state();
    if (!r.accepted) {
      ++rejected_;
      last_rejection_ = u.source + ": " + r.message;
      spdlog::info("voice: rejected {} in state {}: {} ({:.0f} ms)", u.source, StateName(r.state),
                   r.message, r.decode_ms);
    } else {
      ++accepted_;
      reading.mutable_stamp()->set_sequence(++sequence_);
    }
  }
  if (!r.accepted) {
    tell();
    return;
  }
  devices::Stamp* stamp = reading.mutable_stamp();
  stamp->set_device_time_us(static_cast<uint64_t>(heard_ns / 1000));
  stamp->set_receive_monotonic_ns(igms::MonotonicNs());
  stamp->set_receive_unix_ns(igms::UnixNs());
  reading.set_command(ToProto(*r.command));
  reading.set_confidence(r.confidence);
  reading.set_text(std::string(Phrase(*r.command)));
  reading.set_state(ToProto(r.state));
  spdlog::info("voice: accepted \"{}\" (code {}, confidence {:.2f}, {:.0f} ms) from {}",
               Phrase(*r.command), Code(*r.command), r.confidence, r.decode_ms, u.source);
  on_reading_(reading);
  tell();
}

}  // namespace igms::voice
