// The last N grabs, by frame id, each with its edges once the edge pipeline has made them.
//
// Memory: the store holds at most `capacity` frames; inserting one more evicts the oldest.
// A frame handed out (a shared_ptr held by a request in progress) outlives its eviction
// until that request finishes, so the peak is capacity plus the frames of requests in flight.
//
// Lookups tell apart, with a message for a person: an id this run issued and has since
// evicted; an id from before the server's last restart; an id never issued.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "video_server/edges.h"
#include "video_server/stereo_frame.h"

namespace igms::video {

struct StereoEdges {
  EdgeImage left;
  EdgeImage right;
  EdgeOptions options;
  // Wall time from the frame's insertion to its edges being ready, and the detection time
  // of each side on its worker.
  double ready_ms = 0.0;
  double left_ms = 0.0;
  double right_ms = 0.0;
  // Non-empty when detection failed (e.g. out of memory); the maps are then empty.
  std::string error;
};

class FrameRecord {
 public:
  using EdgesCallback = std::function<void(std::shared_ptr<const StereoEdges>)>;

  FrameRecord(uint64_t id, StereoImages images);

  uint64_t id() const { return id_; }
  const StereoImages& images() const { return images_; }
  std::chrono::steady_clock::time_point inserted() const { return inserted_; }

  // The edges, or nullptr when not ready yet.
  std::shared_ptr<const StereoEdges> edges() const;
  // Waits at most `timeout` for the edges; nullptr when they are still not ready.
  std::shared_ptr<const StereoEdges> WaitEdges(std::chrono::milliseconds timeout) const;
  // Calls `done` with the edges: at once (on this thread) when they are ready, otherwise on
  // the thread that finishes them. Never both, never twice.
  void OnEdgesReady(EdgesCallback done);
  // Publishes the edges (the pipeline calls this once) and runs the waiting callbacks.
  void SetEdges(const std::shared_ptr<const StereoEdges>& edges);

  // Bytes held by the images and, once ready, the edges.
  size_t bytes() const;

 private:
  const uint64_t id_;
  const StereoImages images_;
  const std::chrono::steady_clock::time_point inserted_;
  mutable std::mutex mutex_;
  mutable std::condition_variable ready_;
  std::shared_ptr<const StereoEdges> edges_;
  std::vector<EdgesCallback> waiting_;
};

struct FrameLookup {
  std::shared_ptr<FrameRecord> record;
  // Empty when found; otherwise why not.
  std::string error;
  // True when the id was issued by this run and has been evicted.
  bool evicted = false;
};

class FrameStore {
 public:
  // capacity: at least 1. first_id: the first id this run issues (FrameIdSource::first()).
  FrameStore(size_t capacity, uint64_t first_id);

  // Adds a frame (ids must increase), evicting the oldest beyond capacity.
  std::shared_ptr<FrameRecord> Insert(uint64_t id, StereoImages images);
  FrameLookup Find(uint64_t id) const;
  // The newest frame, or nullptr when the store is empty.
  std::shared_ptr<FrameRecord> Newest() const;

  size_t size() const;
  size_t capacity() const { return capacity_; }
  uint64_t evictions() const;
  size_t bytes() const;

 private:
  const size_t capacity_;
  const uint64_t first_id_;
  mutable std::mutex mutex_;
  std::deque<std::shared_ptr<FrameRecord>> frames_;  // oldest first
  uint64_t newest_id_ = 0;
  uint64_t evictions_ = 0;
};

}  // namespace igms::video
