// The receive buffer of a session: bytes that arrived and are not yet framed. Unlike a
// std::string it never zero-fills the room it prepares, and it starts small, so an idle
// session costs a few KB while a 4 MB frame is read into one allocation.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <memory>
#include <string_view>

namespace igms::net {

class ReadBuffer {
 public:
  std::string_view pending() const { return {data_.get() + begin_, end_ - begin_}; }
  void consume(std::size_t n) {
    begin_ += n;
    if (begin_ == end_) begin_ = end_ = 0;
  }
  // Room for at least n more bytes at the end; returns where to write them.
  char* prepare(std::size_t n) {
    if (begin_ > 0 && capacity_ - end_ < n) {
      std::memmove(data_.get(), data_.get() + begin_, end_ - begin_);
      end_ -= begin_;
      begin_ = 0;
    }
    if (capacity_ - end_ < n) {
      const std::size_t capacity = std::max(end_ + n, capacity_ * 2);
      std::unique_ptr<char[]> bigger(new char[capacity]);
      if (end_ > 0) std::memcpy(bigger.get(), data_.get(), end_);
      data_ = std::move(bigger);
      capacity_ = capacity;
    }
    return data_.get() + end_;
  }
  std::size_t room() const { return capacity_ - end_; }
  void commit(std::size_t n) { end_ += n; }
  // Gives a large buffer back once it is empty, so one big frame doesn't pin memory.
  void shrink_if_idle(std::size_t keep) {
    if (begin_ == end_ && capacity_ > keep) {
      data_.reset();
      capacity_ = begin_ = end_ = 0;
    }
  }

 private:
  std::unique_ptr<char[]> data_;
  std::size_t capacity_ = 0;
  std::size_t begin_ = 0;
  std::size_t end_ = 0;
};

}  // namespace igms::net
