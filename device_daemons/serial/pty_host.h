// PtyHost: runs a simulated serial device on a real pseudo-terminal, so a daemon opens it
// with Boost.Asio's serial_port exactly as it would open hardware.
//
// The host owns the master side; the slave side's name is published as a symbolic link
// (options.link_path) that stays the same when the port "vanishes" and returns. A
// pseudo-terminal ignores the baud rate, so the host paces the device's output itself: one
// byte every 10/baud seconds (8N1), 1.04 ms at 9600 baud. Input from the daemon is given to
// the device as it arrives.
//
// Faults, for tests and the sim service: a burst of random garbage bytes in the output, a
// stall (the device says nothing for a while), truncation of the next output chunk, and
// vanishing (the pseudo-terminal is closed and its link removed, then a new one is made).
//
// Threading: the device runs on the host's own thread; WithDevice() runs a function on it
// under the host's lock, so tests can change the device's state safely.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace igms::devices {

// A device's behaviour, called on the host's thread. Output is returned as chunks (one
// reply or report each); the host writes them paced and notes when each chunk's last byte
// went out.
class SimulatedDevice {
 public:
  virtual ~SimulatedDevice() = default;
  // Bytes the daemon wrote. Returns the replies to send.
  virtual std::vector<std::string> OnInput(std::string_view bytes, int64_t now_ns) = 0;
  // Unsolicited output due by now_ns (streaming modes); sets *next_wake_ns to when it next
  // wants to be called (left alone when it has nothing scheduled).
  virtual std::vector<std::string> Poll(int64_t now_ns, int64_t* next_wake_ns) = 0;
};

struct PtyHostOptions {
  std::string link_path;  // required: where the slave's name is published
  unsigned baud = 9600;   // output pacing; 0 writes as fast as the kernel takes it
  uint32_t seed = 1;      // for garbage bytes
  bool Check(std::string* error) const;
};

struct PtyHostStats {
  uint64_t bytes_out = 0;
  uint64_t bytes_in = 0;
  uint64_t chunks_out = 0;
  uint64_t dropped_bytes = 0;  // the slave's buffer was full (nobody reading)
  uint64_t garbage_bytes = 0;
  uint64_t vanishes = 0;
};

class PtyHost {
 public:
  PtyHost(std::unique_ptr<SimulatedDevice> device, PtyHostOptions options);
  ~PtyHost();
  PtyHost(const PtyHost&) = delete;
  PtyHost& operator=(const PtyHost&) = delete;

  // Opens the pseudo-terminal, publishes the link and starts the thread. False with a
  // message on failure.
  bool Start(std::string* error);
  void Stop();
  const std::string& port() const { return options_.link_path; }

  // Faults (thread-safe).
  void InjectGarbage(uint32_t bytes);
  void Stall(std::chrono::milliseconds duration);
  void Vanish(std::chrono::milliseconds duration);
  void TruncateNext();

  // Runs fn on the device under the host's lock.
  void WithDevice(const std::function<void(SimulatedDevice&)>& fn);
  // Called on the host thread with CLOCK_MONOTONIC ns when a chunk's last byte is written.
  void SetOnChunkWritten(std::function<void(int64_t)> fn);
  PtyHostStats stats() const;

 private:
  bool OpenPty(std::string* error);
  void ClosePty();
  void Run();
  void Enqueue(std::vector<std::string> chunks);
  void WriteDue(int64_t now_ns);

  std::unique_ptr<SimulatedDevice> device_;
  PtyHostOptions options_;
  int master_ = -1;
  int slave_ = -1;
  std::thread thread_;
  std::atomic<bool> running_{false};
  mutable std::mutex mutex_;  // device_, queue_, faults, stats_
  struct Pending {
    std::string bytes;
    size_t written = 0;
  };
  std::deque<Pending> queue_;
  int64_t next_slot_ns_ = 0;
  int64_t stall_until_ns_ = 0;
  int64_t vanish_until_ns_ = 0;
  bool truncate_next_ = false;
  uint32_t rng_;
  PtyHostStats stats_;
  std::function<void(int64_t)> on_chunk_written_;
  int wake_pipe_[2] = {-1, -1};
};

}  // namespace igms::devices
