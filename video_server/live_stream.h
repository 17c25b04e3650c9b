// Live stereo video to any number of subscribers, each at its own rate, size and encoding.
//
// One thread captures at the highest rate any subscriber asks for (never faster than the
// backend delivers) and hands each subscriber the frame when its own period has passed.
// Sending never blocks: the network layer's latest-only streams replace a frame a slow
// subscriber has not taken yet by the newer one, so a slow subscriber sees the newest frame,
// never a growing queue, and never slows the others. Frames resized or encoded the same way
// for several subscribers are made once per capture.
//
// Live frames are not kept in the frame store and carry no frame id: to work on a frame,
// grab it (the operator freezes the view first).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "igms/video.pb.h"
#include "video_server/capture_backend.h"

namespace igms::video {

// One subscriber's end: Send returns false once the subscriber is gone (it is then dropped).
using LiveSink = std::function<bool(const LiveFrame&)>;

// Captures one pair for live video; the service passes its serialised backend access.
using LiveCapture = std::function<CaptureResult()>;

class LiveStreamer {
 public:
  explicit LiveStreamer(LiveCapture capture);
  ~LiveStreamer();
  LiveStreamer(const LiveStreamer&) = delete;
  LiveStreamer& operator=(const LiveStreamer&) = delete;

  // Checks the request (rate 0..120 fps, size both zero or 16..8192 each) and adds the
  // subscriber; the error text when the request is refused.
  std::string Add(const LiveRequest& request, LiveSink sink);
  size_t subscribers() const;
  // Live captures so far, and the last capture error (empty when the last one worked).
  uint64_t captures() const;
  std::string last_error() const;

 private:
  struct Subscriber;
  void Run();

  LiveCapture capture_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  bool stop_ = false;
  uint64_t added_ = 0;  // counts subscribers added, to wake the loop for a new one
  std::vector<std::shared_ptr<Subscriber>> subscribers_;
  uint64_t captures_ = 0;
  std::string last_error_;
  std::thread thread_;
};

}  // namespace igms::video
