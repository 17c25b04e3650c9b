// SerialLink against a PtyHost on a real pseudo-terminal: pacing at 9600 baud, the
// watchdog's stale state, and the port vanishing and returning.
#include "device_daemons/serial/serial_link.h"

#include <gtest/gtest.h>

#include <atomic>
#include <mutex>

#include "common/base/clock.h"
#include "device_daemons/serial/pty_host.h"
#include "tests/support/files.h"
#include "tests/support/io_thread.h"
#include "tests/support/wait_for.h"

namespace igms::devices {
namespace {

using igms::testing::IoThread;
using igms::testing::TempPath;
using igms::testing::WaitFor;

// Echoes every input byte back, and when streaming sends 'S' chunks of 10 bytes.
class EchoDevice : public SimulatedDevice {
 public:
  std::vector<std::string> OnInput(std::string_view bytes, int64_t) override {
    return {std::string(bytes)};
  }
  std::vector<std::string> Poll(int64_t now, int64_t* wake) override {
    if (!streaming) return {};
    if (now < next) {
      *wake = std::min(*wake, next);
      return {};
    }
    next = now + 20'000'000;
    *wake = std::min(*wake, next);
    return {std::string(10, 'S')};
  }
  bool streaming = false;
  int64_t next = 0;
};

struct Received {
  std::mutex mutex;
  std::string bytes;
  std::vector<LinkState> states;
  size_t size() {
    std::lock_guard lock(mutex);
    return bytes.size();
  }
  bool saw(LinkState s) {
    std::lock_guard lock(mutex);
    return std::find(states.begin(), states.end(), s) != states.end();
  }
};

TEST(SerialLink, EchoIsPacedLikeA9600BaudLine) {
  std::atomic<int64_t> echoed_ns{0};  // when the line wrote the echo's last chunk
  PtyHost host(std::make_unique<EchoDevice>(), {TempPath("echo"), 9600});
  host.SetOnChunkWritten([&](int64_t at_ns) { echoed_ns = at_ns; });
  std::string error;
  ASSERT_TRUE(host.Start(&error)) << error;
  IoThread io;
  Received rx;
  SerialLink link(
      io.io(), {host.port()},
      [&](const uint8_t* d, size_t n, int64_t) {
        std::lock_guard lock(rx.mutex);
        rx.bytes.append(reinterpret_cast<const char*>(d), n);
      },
      [&](LinkState s, const std::string&) {
        std::lock_guard lock(rx.mutex);
        rx.states.push_back(s);
      });
  link.Start();
  ASSERT_TRUE(WaitFor("the link opening", [&] { return rx.saw(CONNECTING); }));
  const std::string message(96, 'x');
  const int64_t written_ns = MonotonicNs();
  link.Write(message);
  ASSERT_TRUE(WaitFor("the whole message echoed", [&] { return rx.size() >= message.size(); }));
  // The reader can see the last byte before the host has stamped it: the host stamps a chunk
  // under the lock stats() takes, so once stats() counts every byte out, the stamp is there.
  ASSERT_TRUE(WaitFor("the line's stamp of the echo's last byte",
                      [&] { return host.stats().bytes_out >= message.size(); }));
  // 96 bytes at 960 bytes/s take 0.1 s; a pseudo-terminal alone would take microseconds.
  // Timed by the simulated line's stamp of the echo's last byte.
  EXPECT_GE(echoed_ns - written_ns, 95'000'000);
  {
    std::lock_guard lock(rx.mutex);
    EXPECT_EQ(rx.bytes, message);
  }
  link.Stop();
  io.Stop();
}

TEST(SerialLink, SilenceGoesStaleAndVanishingPortIsReopened) {
  auto device = std::make_unique<EchoDevice>();
  device->streaming = true;
  PtyHost host(std::move(device), {TempPath("vanish"), 9600});
  std::string error;
  ASSERT_TRUE(host.Start(&error)) << error;
  IoThread io;
  Received rx;
  SerialLinkOptions options{host.port()};
  options.silence_timeout = std::chrono::milliseconds(150);
  SerialLink link(
      io.io(), options,
      [&](const uint8_t* d, size_t n, int64_t) {
        std::lock_guard lock(rx.mutex);
        rx.bytes.append(reinterpret_cast<const char*>(d), n);
      },
      [&](LinkState s, const std::string&) {
        std::lock_guard lock(rx.mutex);
        rx.states.push_back(s);
      });
  link.Start();
  ASSERT_TRUE(
      WaitFor("the link up and 50 bytes in", [&] { return rx.saw(CONNECTED) && rx.size() > 50; }));

  host.Stall(std::chrono::milliseconds(250));
  ASSERT_TRUE(WaitFor(
      "the link gone stale", [&] { return rx.saw(STALE); }, std::chrono::seconds(5)));

  const size_t before = rx.size();
  host.Vanish(std::chrono::milliseconds(300));
  ASSERT_TRUE(WaitFor(
      "the link reopening", [&] { return rx.saw(REOPENING); }, std::chrono::seconds(5)));
  // Back: bytes flow again through a new pseudo-terminal behind the same link path.
  ASSERT_TRUE(WaitFor(
      "100 bytes after reopening", [&] { return rx.size() > before + 100; },
      std::chrono::seconds(10)));
  EXPECT_GE(link.reopens(), 1u);
  EXPECT_GE(host.stats().vanishes, 1u);
  link.Stop();
  io.Stop();
}

TEST(SerialLink, MissingPortKeepsRetryingWithoutCrashing) {
  IoThread io;
  std::atomic<int> reopenings{0};
  SerialLinkOptions options{TempPath("absent")};
  options.backoff_min = std::chrono::milliseconds(5);
  options.backoff_max = std::chrono::milliseconds(40);
  SerialLink link(
      io.io(), options, [](const uint8_t*, size_t, int64_t) {},
      [&](LinkState s, const std::string&) {
        if (s == REOPENING) ++reopenings;
      });
  link.Start();
  EXPECT_TRUE(WaitFor(
      "four reopen attempts", [&] { return link.reopens() >= 4; }, std::chrono::seconds(5)));
  EXPECT_EQ(reopenings.load(), 1);  // reported once, not on every retry
  link.Stop();
  io.Stop();
}

}  // namespace
}  // namespace igms::devices
