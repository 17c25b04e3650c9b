// The live stereo video behind the window (VideoService.Live): its own connection to the
// video server, on its own network thread, keeping only the newest pair (a slow window skips
// frames; it never queues them). The overlay settings (u/v offset, key level) are read at
// connection and written with VideoService.SetOverlay.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "control/app/control_app.h"
#include "control/window/view_from_session.h"

namespace igms::control {

// The largest live message the window accepts: a pair of 1280 x 1024 colour images (the
// thesis's viewer resolution, section 2.1.3, from real cameras) sent raw is 7.9 MB; twice
// that leaves room for the envelope and larger sensors.
inline constexpr size_t kLiveMaxFrameBytes = 16u << 20;

struct LiveVideoOptions {
  PeerAddress address;
  std::string token;
  std::string client_name = "control-window";
  double fps = 60;  // asked of the server (it sends at most its capture rate)
  // No frame for this long while connected also counts as lost.
  std::chrono::milliseconds stale_after{2000};
};

struct LiveStats {
  uint64_t frames = 0;   // received
  uint64_t skipped = 0;  // gaps in the server's sequence
  // Capture to receipt, the newest frame: the capture stamp (the video host's clock) put on
  // this host's clock with the offset pings estimated, once they have.
  double latency_ms = 0;
  double clock_offset_ms = 0;  // the video server's clock minus this host's
  double clock_bound_ms = 0;   // the offset is true within this (half the best round trip)
  int clock_pings = 0;         // the pings it was estimated from; 0: not yet
  double rate_fps = 0;         // over the last second
};

class LiveVideo {
 public:
  static std::unique_ptr<LiveVideo> Start(LiveVideoOptions options);
  ~LiveVideo();
  LiveVideo(const LiveVideo&) = delete;
  LiveVideo& operator=(const LiveVideo&) = delete;

  // The newest pair if it is newer than `after` (a sequence); nullopt otherwise.
  std::optional<StereoFrame> Newer(uint64_t after) const;
  // Not connected, or connected with no frame for stale_after.
  bool lost() const;
  LiveStats stats() const;
  // The overlay settings as the server last reported them (zero before).
  video::OverlaySettings overlay() const;
  // Moves the video's offset by (du, dv) pixels and stores it on the server.
  void MoveOffset(int du, int dv);
  // The grabbed pair of a frozen session (VideoService.GetImages of `frame_id`): FetchGrab
  // asks for it once; Grabbed has it when it has arrived. Its sequence is kGrabSequence +
  // frame id, apart from the live sequences.
  void FetchGrab(uint64_t frame_id);
  std::optional<StereoFrame> Grabbed(uint64_t frame_id) const;
  static constexpr uint64_t kGrabSequence = uint64_t{1} << 62;

  struct Impl;

 private:
  explicit LiveVideo(std::shared_ptr<Impl> impl);
  std::shared_ptr<Impl> impl_;
};

}  // namespace igms::control
