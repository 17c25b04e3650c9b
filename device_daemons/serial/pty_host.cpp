#include "device_daemons/serial/pty_host.h"

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>

#include "common/base/clock.h"
#include "common/base/errno_text.h"

namespace igms::devices {
namespace {

// Time one character takes on an asynchronous line (start bit, 8 data bits, stop bit).
std::chrono::nanoseconds ByteTime(unsigned baud) {
  return std::chrono::nanoseconds(10'000'000'000LL / (baud == 0 ? 1 : baud));
}

}  // namespace

bool PtyHostOptions::Check(std::string* error) const {
  if (link_path.empty()) {
    *error = "the simulator needs a link path for its pseudo-terminal";
    return false;
  }
  return true;
}

PtyHost::PtyHost(std::unique_ptr<SimulatedDevice> device, PtyHostOptions options)
    : device_(std::move(device)), options_(std::move(options)), rng_(options_.seed | 1U) {}

PtyHost::~PtyHost() { Stop(); }

bool PtyHost::OpenPty(std::string* error) {
  char name[256] = {};
  if (openpty(&master_, &slave_, name, nullptr, nullptr) != 0) {
    *error = std::string("openpty failed: ") + ErrnoText(errno);
    return false;
  }
  termios tio{};
  tcgetattr(slave_, &tio);
  cfmakeraw(&tio);
  tcsetattr(slave_, TCSANOW, &tio);
  fcntl(master_, F_SETFL, fcntl(master_, F_GETFL) | O_NONBLOCK);
  fcntl(master_, F_SETFD, FD_CLOEXEC);
  fcntl(slave_, F_SETFD, FD_CLOEXEC);
  ::unlink(options_.link_path.c_str());
  if (::symlink(name, options_.link_path.c_str()) != 0) {
    *error = "cannot link " + options_.link_path + " to " + name + ": " + ErrnoText(errno);
    ClosePty();
    return false;
  }
  return true;
}

void PtyHost::ClosePty() {
  if (master_ >= 0) ::close(master_);
  if (slave_ >= 0) ::close(slave_);
  master_ = slave_ = -1;
  ::unlink(options_.link_path.c_str());
}

bool PtyHost::Start(std::string* error) {
  if (!options_.Check(error)) return false;
  if (pipe2(wake_pipe_, O_NONBLOCK | O_CLOEXEC) != 0) {
    *error = std::string("pipe failed: ") + ErrnoText(errno);
    return false;
  }
  if (!OpenPty(error)) return false;
  running_ = true;
  thread_ = std::thread([this] { Run(); });
  return true;
}

void PtyHost::Stop() {
  if (running_.exchange(false)) {
    const char c = 'x';
    [[maybe_unused]] auto n = ::write(wake_pipe_[1], &c, 1);
    thread_.join();
  }
  std::lock_guard lock(mutex_);
  ClosePty();
  for (int& fd : wake_pipe_) {
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
}

void PtyHost::InjectGarbage(uint32_t bytes) {
  std::lock_guard lock(mutex_);
  std::string junk;
  for (uint32_t i = 0; i < bytes; ++i) {
    rng_ = rng_ * 1664525U + 1013904223U;
    junk.push_back(static_cast<char>(rng_ >> 24));
  }
  stats_.garbage_bytes += bytes;
  if (queue_.empty()) next_slot_ns_ = std::max(next_slot_ns_, MonotonicNs());
  queue_.push_back({std::move(junk), 0});
}

void PtyHost::Stall(std::chrono::milliseconds duration) {
  std::lock_guard lock(mutex_);
  stall_until_ns_ = MonotonicNs() + duration.count() * 1'000'000;
}

void PtyHost::Vanish(std::chrono::milliseconds duration) {
  std::lock_guard lock(mutex_);
  vanish_until_ns_ = MonotonicNs() + duration.count() * 1'000'000;
}

void PtyHost::TruncateNext() {
  std::lock_guard lock(mutex_);
  truncate_next_ = true;
}

void PtyHost::WithDevice(const std::function<void(SimulatedDevice&)>& fn) {
  std::lock_guard lock(mutex_);
  fn(*device_);
}

void PtyHost::SetOnChunkWritten(std::function<void(int64_t)> fn) {
  std::lock_guard lock(mutex_);
  on_chunk_written_ = std::move(fn);
}

PtyHostStats PtyHost::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void PtyHost::Enqueue(std::vector<std::string> chunks) {
  for (auto& chunk : chunks) {
    if (chunk.empty()) continue;
    if (queue_.empty()) next_slot_ns_ = std::max(next_slot_ns_, MonotonicNs());
    if (truncate_next_) {
      chunk.resize(chunk.size() / 2);
      truncate_next_ = false;
    }
    queue_.push_back({std::move(chunk), 0});
  }
}

// Writes every byte whose slot on the simulated line has come. Slots follow each other at
// the line's byte time from when the line last went busy, so a late wake-up (a loaded
// machine) writes the overdue bytes at once and the line keeps its average rate.
void PtyHost::WriteDue(int64_t now_ns) {
  const int64_t byte_ns = options_.baud == 0 ? 0 : ByteTime(options_.baud).count();
  while (!queue_.empty() && now_ns >= stall_until_ns_ && now_ns >= next_slot_ns_) {
    Pending& p = queue_.front();
    const ssize_t n = ::write(master_, p.bytes.data() + p.written, 1);
    if (n == 1) {
      ++stats_.bytes_out;
    } else {
      ++stats_.dropped_bytes;  // nobody is draining the slave: the byte is lost, as on a line
    }
    next_slot_ns_ += byte_ns;
    if (++p.written == p.bytes.size()) {
      ++stats_.chunks_out;
      if (on_chunk_written_) on_chunk_written_(MonotonicNs());
      queue_.pop_front();
    }
  }
  // An idle line starts its next byte whenever one comes.
  if (queue_.empty() || now_ns < stall_until_ns_) next_slot_ns_ = std::max(next_slot_ns_, now_ns);
}

void PtyHost::Run() {
  char buffer[512];
  while (running_) {
    int64_t wake_ns;
    int master;
    {
      std::lock_guard lock(mutex_);
      const int64_t now = MonotonicNs();
      wake_ns = now + 100'000'000;
      if (vanish_until_ns_ > 0 && master_ >= 0 && now < vanish_until_ns_) {
        ClosePty();
        queue_.clear();
        ++stats_.vanishes;
      }
      if (master_ < 0) {
        std::string error;
        if (now >= vanish_until_ns_ && OpenPty(&error)) {
          vanish_until_ns_ = 0;
        } else {
          wake_ns = std::min(wake_ns, std::max(vanish_until_ns_, now + 10'000'000));
        }
      }
      if (master_ >= 0) {
        Enqueue(device_->Poll(now, &wake_ns));
        WriteDue(now);
        if (!queue_.empty()) wake_ns = std::min(wake_ns, std::max(next_slot_ns_, stall_until_ns_));
      }
      master = master_;
    }
    pollfd fds[2] = {{wake_pipe_[0], POLLIN, 0}, {master, POLLIN, 0}};
    const int64_t wait_ns = std::max<int64_t>(0, wake_ns - MonotonicNs());
    timespec timeout{static_cast<time_t>(wait_ns / 1'000'000'000),
                     static_cast<long>(wait_ns % 1'000'000'000)};
    const int ready = ppoll(fds, master >= 0 ? 2 : 1, &timeout, nullptr);
    if (ready <= 0) continue;
    if (fds[0].revents & POLLIN) {
      while (::read(wake_pipe_[0], buffer, sizeof buffer) > 0) {
      }
    }
    if (master >= 0 && (fds[1].revents & POLLIN)) {
      const ssize_t n = ::read(master, buffer, sizeof buffer);
      if (n > 0) {
        std::lock_guard lock(mutex_);
        stats_.bytes_in += static_cast<uint64_t>(n);
        Enqueue(device_->OnInput(std::string_view(buffer, static_cast<size_t>(n)), MonotonicNs()));
      }
    } else if (master >= 0 && (fds[1].revents & (POLLHUP | POLLERR))) {
      // No one has the slave open: avoid spinning on the hang-up.
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
}

}  // namespace igms::devices
