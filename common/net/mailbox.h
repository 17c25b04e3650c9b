// A bounded hand-over from the network thread to another thread (a render loop) that must
// never block: the producer pushes, the consumer drains with TryPop. When full, the oldest
// message is dropped, so a stalled consumer sees the newest data when it comes back.
#pragma once

#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>

namespace igms::net {

template <class T>
class Mailbox {
 public:
  explicit Mailbox(std::size_t capacity = 64) : capacity_(capacity == 0 ? 1 : capacity) {}

  void Push(T value) {
    std::lock_guard lock(mutex_);
    if (items_.size() >= capacity_) {
      items_.pop_front();
      ++dropped_;
    }
    items_.push_back(std::move(value));
  }

  std::optional<T> TryPop() {
    std::lock_guard lock(mutex_);
    if (items_.empty()) return std::nullopt;
    T value = std::move(items_.front());
    items_.pop_front();
    return value;
  }

  std::size_t size() const {
    std::lock_guard lock(mutex_);
    return items_.size();
  }
  std::size_t dropped() const {
    std::lock_guard lock(mutex_);
    return dropped_;
  }

 private:
  mutable std::mutex mutex_;
  std::deque<T> items_;
  std::size_t capacity_;
  std::size_t dropped_ = 0;
};

}  // namespace igms::net
