// ReadingHub: hands each new reading of a daemon to its TCP subscribers, each at the rate
// it asked for, and to the recording when there is one.
//
// A subscriber asking rate_hz 0 (or more than the device gives) gets every reading; one
// asking less gets the newest reading once at least 1/rate_hz has passed since the last it
// was sent. Subscribers use the server's latest_only streams, so a slow one gets the newest
// reading and never a growing queue. Closed subscribers are dropped on the next Publish.
//
// Thread-safe.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "common/base/clock.h"
#include "common/net/server.h"
#include "device_daemons/serial/recording.h"
#include "igms/devices.pb.h"

namespace igms::devices {

inline void WrapReading(const ViewerState& m, Reading* r) { *r->mutable_viewer() = m; }
inline void WrapReading(const JoystickState& m, Reading* r) { *r->mutable_joystick() = m; }
inline void WrapReading(const RangerState& m, Reading* r) { *r->mutable_ranger() = m; }
inline void WrapReading(const PlatformState& m, Reading* r) { *r->mutable_platform() = m; }
inline void WrapReading(const VoiceState& m, Reading* r) { *r->mutable_voice() = m; }

inline const ViewerState* UnwrapReading(const Reading& r, const ViewerState*) {
  return r.has_viewer() ? &r.viewer() : nullptr;
}
inline const JoystickState* UnwrapReading(const Reading& r, const JoystickState*) {
  return r.has_joystick() ? &r.joystick() : nullptr;
}
inline const RangerState* UnwrapReading(const Reading& r, const RangerState*) {
  return r.has_ranger() ? &r.ranger() : nullptr;
}
inline const PlatformState* UnwrapReading(const Reading& r, const PlatformState*) {
  return r.has_platform() ? &r.platform() : nullptr;
}
inline const VoiceState* UnwrapReading(const Reading& r, const VoiceState*) {
  return r.has_voice() ? &r.voice() : nullptr;
}

template <class Msg>
class ReadingHub {
 public:
  void Subscribe(std::shared_ptr<net::Publisher<Msg>> publisher, double rate_hz) {
    std::lock_guard lock(mutex_);
    const int64_t period = rate_hz > 0 ? static_cast<int64_t>(1e9 / rate_hz) : 0;
    subscribers_.push_back({std::move(publisher), period, 0});
    if (has_latest_) subscribers_.back().publisher->Send(latest_);
  }

  // Records the writer's readings too, from now on.
  void Record(std::unique_ptr<RecordingWriter> writer) {
    std::lock_guard lock(mutex_);
    recorder_ = std::move(writer);
  }

  void Publish(const Msg& message) {
    std::lock_guard lock(mutex_);
    latest_ = message;
    has_latest_ = true;
    ++published_;
    if (recorder_) {
      Reading r;
      WrapReading(message, &r);
      recorder_->Append(r);
    }
    const int64_t now = MonotonicNs();
    std::erase_if(subscribers_, [&](Subscriber& s) {
      if (now - s.last_sent_ns < s.period_ns) return s.publisher->closed();
      s.last_sent_ns = now;
      return !s.publisher->Send(message);
    });
  }

  bool Latest(Msg* out) const {
    std::lock_guard lock(mutex_);
    if (has_latest_) *out = latest_;
    return has_latest_;
  }
  size_t subscribers() const {
    std::lock_guard lock(mutex_);
    return subscribers_.size();
  }
  uint64_t published() const {
    std::lock_guard lock(mutex_);
    return published_;
  }

 private:
  struct Subscriber {
    std::shared_ptr<net::Publisher<Msg>> publisher;
    int64_t period_ns;
    int64_t last_sent_ns;
  };
  mutable std::mutex mutex_;
  std::vector<Subscriber> subscribers_;
  std::unique_ptr<RecordingWriter> recorder_;
  Msg latest_;
  bool has_latest_ = false;
  uint64_t published_ = 0;
};

}  // namespace igms::devices
