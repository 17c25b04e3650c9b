// The video server's requests (igms.video.VideoService, docs/protocol-video.md) on top of a
// capture backend, the frame store, the edge pipeline, live video and the overlay settings.
//
//  - Grab captures a pair now (on the capture thread, so the network thread never waits on
//    a camera), gives it the next frame id, stores it and starts its edge detection at once.
//  - GetImages / GetEdges serve a stored frame, whole or a region, raw or PNG; GetEdges
//    waits (without holding a thread) until the frame's edges are ready or its timeout ends.
//  - Live streams frames to subscribers (live_stream.h).
//  - GetOverlay / SetOverlay keep the overlay settings, in a file that survives restarts.
// Bad input (unknown or evicted frame, region outside the image, absurd sizes) is an error
// response with a message; nothing a client sends stops the server.
#pragma once

#include <atomic>
#include <boost/asio/io_context.hpp>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "common/net/server.h"
#include "common/wire/image_codec.h"
#include "igms/video.pb.h"
#include "video_server/capture_backend.h"
#include "video_server/edge_pipeline.h"
#include "video_server/frame_id.h"
#include "video_server/frame_store.h"
#include "video_server/live_stream.h"
#include "video_server/overlay_settings.h"
#include "video_server/worker_pool.h"

namespace igms::video {

struct VideoServiceOptions {
  // Grabs kept (the frame store's capacity).
  size_t store_capacity = 16;
  // Edge detection threads (2: the left and right image of a grab in parallel).
  int edge_threads = 2;
  EdgeOptions edges;
  // ImageEncoding when a request leaves it unspecified.
  wire::ImageEncoding default_encoding = wire::ImageEncoding::kPng;
  // Overlay settings file; empty keeps them in memory only.
  std::string overlay_path;
  // Threads that encode images and edge maps for responses.
  int encode_threads = 2;
  // The lab's calibration as loaded, for GetStatus: its file and CalibrationHash
  // (common/calibration/calibration_hash.h); empty when there is none.
  std::string calibration_file;
  std::string calibration_sha256;

  bool Check(std::string* error) const;
};

// The platform pose now (zero when the lab has no platform).
using PoseSource = std::function<PoseStamp()>;

class VideoService {
 public:
  // `io` runs the server (its timers bound GetEdges waits). Options must pass Check()
  // (throws std::invalid_argument). `overlay` is the settings loaded at start.
  VideoService(boost::asio::io_context& io, std::unique_ptr<CaptureBackend> backend,
               VideoServiceOptions options, Overlay overlay, PoseSource pose = nullptr);
  ~VideoService();

  // Registers every method of igms.video.VideoService on `server`, which must outlive the
  // service (GetStatus reports the address it listens at).
  void Register(net::Server& server);

  // The same requests, callable directly (the handlers use them; so can tests).
  net::Status Grab(GrabResponse& response);
  net::Status GetImages(const GetImagesRequest& request, GetImagesResponse& response);
  // Calls done exactly once, from a worker or timer thread.
  void GetEdges(const GetEdgesRequest& request,
                std::function<void(const net::Status&, const GetEdgesResponse&)> done);
  net::Status SetOverlay(const SetOverlayRequest& request, SetOverlayResponse& response);
  StatusResponse Status() const;

  FrameStore& store() { return store_; }

 private:
  CaptureResult CaptureNow();

  boost::asio::io_context& io_;
  const net::Server* server_ = nullptr;  // set by Register
  const VideoServiceOptions options_;
  std::unique_ptr<CaptureBackend> backend_;
  std::mutex backend_mutex_;  // one capture at a time: grabs and live video share it
  PoseSource pose_;
  std::mutex insert_mutex_;
  FrameIdSource ids_;
  FrameStore store_;
  OverlayStore overlay_;
  std::atomic<uint64_t> grabs_{0};
  // Destroyed in reverse: live video and grabs stop first, then the pipeline finishes its
  // queued frames, whose waiting requests still find the encode pool.
  WorkerPool encode_pool_;
  EdgePipeline pipeline_;
  WorkerPool capture_pool_;
  LiveStreamer live_;
};

}  // namespace igms::video
