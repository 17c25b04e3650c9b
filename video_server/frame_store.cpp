#include "video_server/frame_store.h"

#include <algorithm>
#include <stdexcept>

namespace igms::video {

FrameRecord::FrameRecord(uint64_t id, StereoImages images)
    : id_(id), images_(std::move(images)), inserted_(std::chrono::steady_clock::now()) {}

std::shared_ptr<const StereoEdges> FrameRecord::edges() const {
  std::lock_guard lock(mutex_);
  return edges_;
}

std::shared_ptr<const StereoEdges> FrameRecord::WaitEdges(std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mutex_);
  ready_.wait_for(lock, timeout, [&] { return edges_ != nullptr; });
  return edges_;
}

void FrameRecord::OnEdgesReady(EdgesCallback done) {
  std::shared_ptr<const StereoEdges> ready;
  {
    std::lock_guard lock(mutex_);
    if (!edges_) {
      waiting_.push_back(std::move(done));
      return;
    }
    ready = edges_;
  }
  done(ready);
}

void FrameRecord::SetEdges(const std::shared_ptr<const StereoEdges>& edges) {
  std::vector<EdgesCallback> waiting;
  {
    std::lock_guard lock(mutex_);
    if (edges_) throw std::logic_error("edges of frame " + std::to_string(id_) + " set twice");
    edges_ = edges;
    waiting.swap(waiting_);
  }
  ready_.notify_all();
  // Outside the lock: a callback may look at this record again.
  for (EdgesCallback& done : waiting) done(edges);
}

size_t FrameRecord::bytes() const {
  size_t total = images_.left.total() * images_.left.elemSize() +
                 images_.right.total() * images_.right.elemSize();
  if (auto ready = edges()) total += ready->left.bytes() + ready->right.bytes();
  return total;
}

FrameStore::FrameStore(size_t capacity, uint64_t first_id)
    : capacity_(std::max<size_t>(capacity, 1)), first_id_(first_id) {}

std::shared_ptr<FrameRecord> FrameStore::Insert(uint64_t id, StereoImages images) {
  auto record = std::make_shared<FrameRecord>(id, std::move(images));
  std::lock_guard lock(mutex_);
  if (!frames_.empty() && id <= newest_id_) {
    throw std::logic_error("frame ids must increase: " + std::to_string(id) + " after " +
                           std::to_string(newest_id_));
  }
  frames_.push_back(record);
  newest_id_ = id;
  while (frames_.size() > capacity_) {
    frames_.pop_front();
    ++evictions_;
  }
  return record;
}

FrameLookup FrameStore::Find(uint64_t id) const {
  FrameLookup lookup;
  std::lock_guard lock(mutex_);
  auto it = std::lower_bound(frames_.begin(), frames_.end(), id,
                             [](const auto& record, uint64_t key) { return record->id() < key; });
  if (it != frames_.end() && (*it)->id() == id) {
    lookup.record = *it;
    return lookup;
  }
  const std::string held = frames_.empty()
                               ? "the store is empty"
                               : "the store holds frames " + std::to_string(frames_.front()->id()) +
                                     " to " + std::to_string(frames_.back()->id());
  if (id < first_id_) {
    lookup.error = "unknown frame id " + std::to_string(id) +
                   ": not grabbed since the video server started (" + held + "); grab again";
  } else if (!frames_.empty() && id < frames_.front()->id()) {
    lookup.evicted = true;
    lookup.error = "frame " + std::to_string(id) + " was evicted: the store keeps the last " +
                   std::to_string(capacity_) + " grabs (" + held + "); grab again";
  } else {
    lookup.error =
        "unknown frame id " + std::to_string(id) + ": no such frame was grabbed (" + held + ")";
  }
  return lookup;
}

std::shared_ptr<FrameRecord> FrameStore::Newest() const {
  std::lock_guard lock(mutex_);
  return frames_.empty() ? nullptr : frames_.back();
}

size_t FrameStore::size() const {
  std::lock_guard lock(mutex_);
  return frames_.size();
}

uint64_t FrameStore::evictions() const {
  std::lock_guard lock(mutex_);
  return evictions_;
}

size_t FrameStore::bytes() const {
  std::lock_guard lock(mutex_);
  size_t total = 0;
  for (const auto& record : frames_) total += record->bytes();
  return total;
}

}  // namespace igms::video
