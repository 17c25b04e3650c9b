// Device daemons: readings per second at each device's full rate, added latency from the
// simulator writing a reading's last byte to a TCP subscriber receiving it (p50, p99;
// target under 2 ms), and each daemon's resident memory (target under 30 MB).
//
// The simulator runs here on a real pseudo-terminal paced at 9600 baud; the daemon is the
// real process, started with --serial on that pseudo-terminal as it would be on hardware.
// Baseline, same run: the same simulator read in-process by a bare SerialLink (no daemon,
// no TCP). Last, the gamepad stand-in (--gamepad) fed js_event records through a FIFO. Both clocks
// are CLOCK_MONOTONIC, shared by processes on one host.
//
//   build/bench/bench_devices [seconds per device, default 5]
#include <linux/joystick.h>
#include <sys/stat.h>

#include <algorithm>
#include <boost/asio/io_context.hpp>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>
#include <vector>

#include "bench/bench_main.h"
#include "common/base/clock.h"
#include "common/net/client.h"
#include "common/sim/ranger/site_ranger.h"
#include "common/stats/percentile.h"
#include "device_daemons/joystick/flybox_sim.h"
#include "device_daemons/joystick/gamepad.h"
#include "device_daemons/platform/molly_sim.h"
#include "device_daemons/ranger/ranger_sim.h"
#include "device_daemons/serial/pty_host.h"
#include "device_daemons/serial/serial_link.h"
#include "device_daemons/viewer/viewer_sim.h"
#include "tests/support/daemon_process.h"
#include "tests/support/files.h"
#include "tests/support/io_thread.h"

namespace {

using namespace igms::devices;
using igms::testing::IoThread;
using testing::DaemonProcess;

// Times at which the simulator finished writing each chunk.
class ChunkTimes {
 public:
  void Add(int64_t t) {
    std::lock_guard lock(mutex_);
    times_.push_back(t);
  }
  // The latest chunk end at or before t (0 if none).
  int64_t LastBefore(int64_t t) {
    std::lock_guard lock(mutex_);
    auto it = std::upper_bound(times_.begin(), times_.end(), t);
    return it == times_.begin() ? 0 : *(it - 1);
  }

 private:
  std::mutex mutex_;
  std::vector<int64_t> times_;
};

struct Figures {
  double rate = 0, p50_ms = 0, p99_ms = 0;
  size_t n = 0;
};

Figures Summarise(const std::vector<double>& latencies_ms, double seconds) {
  Figures f;
  f.n = latencies_ms.size();
  f.rate = static_cast<double>(f.n) / seconds;
  if (latencies_ms.empty()) return f;
  f.p50_ms = igms::stats::Median(latencies_ms);
  f.p99_ms = igms::stats::Percentile(latencies_ms, 0.99);
  return f;
}

double RssMb(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string key;
  while (in >> key) {
    if (key == "VmRSS:") {
      double kb = 0;
      in >> kb;
      return kb / 1024.0;
    }
  }
  return 0;
}

std::unique_ptr<PtyHost> StartSim(std::unique_ptr<SimulatedDevice> device, const std::string& name,
                                  ChunkTimes* times) {
  auto host = std::make_unique<PtyHost>(std::move(device),
                                        PtyHostOptions{igms::testing::TempPath(name), 9600});
  host->SetOnChunkWritten([times](int64_t t) { times->Add(t); });
  std::string error;
  if (!host->Start(&error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::exit(1);
  }
  return host;
}

// Baseline: a bare SerialLink reading the simulator; a reading ends with its last byte.
// request: what to write periodically (polled devices), empty for none.
Figures Baseline(std::unique_ptr<SimulatedDevice> device, const std::string& init,
                 const std::string& request, double hz, size_t reply_length, double seconds) {
  ChunkTimes times;
  auto host = StartSim(std::move(device), "baseline", &times);
  IoThread io;
  std::mutex mutex;
  std::vector<double> latencies;
  size_t pending = 0;
  bool measuring = false;
  SerialLink link(
      io.io(), {host->port()},
      [&](const uint8_t*, size_t n, int64_t now) {
        std::lock_guard lock(mutex);
        pending += n;
        while (pending >= reply_length) {
          pending -= reply_length;
          if (measuring && pending == 0)
            latencies.push_back(static_cast<double>(now - times.LastBefore(now)) / 1e6);
        }
      },
      nullptr);
  link.Start();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  if (!init.empty()) link.Write(init);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  {
    std::lock_guard lock(mutex);
    pending = 0;
    measuring = true;
  }
  const auto end = std::chrono::steady_clock::now() +
                   std::chrono::nanoseconds(static_cast<int64_t>(seconds * 1e9));
  auto next = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() < end) {
    if (!request.empty()) link.Write(request);
    next += std::chrono::nanoseconds(static_cast<int64_t>(1e9 / hz));
    std::this_thread::sleep_until(std::min(next, end));
  }
  link.Stop();
  io.Stop();
  host->Stop();
  std::lock_guard lock(mutex);
  return Summarise(latencies, seconds);
}

template <class Msg>
void RunDevice(const std::string& label, const std::string& program, std::vector<std::string> extra,
               std::unique_ptr<SimulatedDevice> device, const std::string& method, double seconds,
               const Figures& baseline) {
  ChunkTimes times;
  auto host = StartSim(std::move(device), label, &times);
  std::vector<std::string> args{"--serial", host->port(), "--port", "0"};
  args.insert(args.end(), extra.begin(), extra.end());
  DaemonProcess daemon(program, args);
  const uint16_t port = daemon.WaitForPort();
  if (port == 0) {
    std::fprintf(stderr, "%s did not start:\n%s\n", program.c_str(), daemon.Log().c_str());
    return;
  }
  IoThread io;
  igms::net::ClientOptions options;
  options.port = port;
  igms::net::Client client(io.io(), options);
  client.Start();
  std::mutex mutex;
  std::vector<double> latencies, serial_part;
  bool measuring = false;
  client.Subscribe<Msg>(method, igms::devices::SubscribeRequest(), [&](const Msg& m) {
    const int64_t now = igms::MonotonicNs();
    std::lock_guard lock(mutex);
    if (!measuring) return;
    const int64_t last_byte = times.LastBefore(m.stamp().receive_monotonic_ns());
    latencies.push_back(static_cast<double>(now - last_byte) / 1e6);
    serial_part.push_back(static_cast<double>(m.stamp().receive_monotonic_ns() - last_byte) / 1e6);
  });
  std::this_thread::sleep_for(std::chrono::seconds(2));  // identify, configure, settle
  {
    std::lock_guard lock(mutex);
    measuring = true;
  }
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  Figures f, s;
  {
    std::lock_guard lock(mutex);
    measuring = false;
    f = Summarise(latencies, seconds);
    s = Summarise(serial_part, seconds);
  }
  const double rss = RssMb(daemon.pid());
  client.Stop();
  io.Stop();
  daemon.Stop();
  host->Stop();
  std::printf(
      "%-9s %8.1f/s   last byte -> subscriber p50 %6.3f ms  p99 %6.3f ms   (of which last byte -> "
      "daemon p50 %6.3f ms)   "
      "baseline bare SerialLink p50 %6.3f ms p99 %6.3f ms   RSS %5.1f MB\n",
      label.c_str(), f.rate, f.p50_ms, f.p99_ms, s.p50_ms, baseline.p50_ms, baseline.p99_ms, rss);
}

// The gamepad stand-in: js_event records written into a FIFO at 50 Hz, each a new x value;
// latency from the write() to the subscriber receiving that value. Baseline: the same
// records read from a FIFO by a blocking read() in this process.
int OpenWriter(const std::string& path) {
  for (int i = 0; i < 5000; ++i) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK);
    if (fd >= 0) return fd;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return -1;
}

// Writes `seconds` of x-axis events at 50 Hz; value i is written at times[i].
void WriteEvents(int fd, double seconds, std::vector<int64_t>* times, std::mutex* mutex) {
  const int count = static_cast<int>(seconds * 50);
  auto next = std::chrono::steady_clock::now();
  for (int i = 1; i <= count; ++i) {
    const std::string e = EncodeJsEvent(static_cast<uint32_t>(i),
                                        static_cast<int16_t>(-(i % 30000)), JS_EVENT_AXIS, 1);
    {
      // Stamped just before the write, so the reader never sees a value before its time.
      std::lock_guard lock(*mutex);
      times->push_back(igms::MonotonicNs());
    }
    if (::write(fd, e.data(), e.size()) != static_cast<ssize_t>(e.size())) {
      std::lock_guard lock(*mutex);
      times->back() = 0;
    }
    next += std::chrono::milliseconds(20);
    std::this_thread::sleep_until(next);
  }
}

void RunGamepad(double seconds) {
  const std::string fifo = igms::testing::TempPath("bench-js");
  ::mkfifo(fifo.c_str(), 0600);
  std::vector<int64_t> times;
  std::mutex mutex;
  // Baseline.
  std::vector<double> base;
  {
    std::thread reader([&] {
      const int fd = ::open(fifo.c_str(), O_RDONLY);
      char buf[8];
      size_t i = 0;
      while (::read(fd, buf, sizeof buf) == static_cast<ssize_t>(sizeof buf)) {
        const int64_t now = igms::MonotonicNs();
        std::lock_guard lock(mutex);
        if (i < times.size() && times[i] > 0)
          base.push_back(static_cast<double>(now - times[i]) / 1e6);
        ++i;
      }
      ::close(fd);
    });
    const int fd = OpenWriter(fifo);
    WriteEvents(fd, seconds, &times, &mutex);
    ::close(fd);
    reader.join();
  }
  const Figures baseline = Summarise(base, seconds);
  times.clear();
  DaemonProcess daemon("igms-joystickd", {"--gamepad", fifo, "--port", "0"});
  const uint16_t port = daemon.WaitForPort();
  if (port == 0) {
    std::fprintf(stderr, "igms-joystickd did not start:\n%s\n", daemon.Log().c_str());
    return;
  }
  IoThread io;
  igms::net::ClientOptions options;
  options.port = port;
  igms::net::Client client(io.io(), options);
  client.Start();
  std::vector<double> latencies;
  size_t readings = 0;
  int last_index = 0;
  client.Subscribe<igms::devices::JoystickState>(
      "igms.devices.JoystickService.Live", igms::devices::SubscribeRequest(),
      [&](const igms::devices::JoystickState& m) {
        const int64_t now = igms::MonotonicNs();
        std::lock_guard lock(mutex);
        ++readings;
        const int index = static_cast<int>(std::lround(m.x() * 32767.0));  // x = -axis
        if (index <= last_index || index > static_cast<int>(times.size())) return;
        last_index = index;
        if (times[index - 1] > 0)
          latencies.push_back(static_cast<double>(now - times[index - 1]) / 1e6);
      });
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const int fd = OpenWriter(fifo);
  size_t before = 0;
  {
    std::lock_guard lock(mutex);
    before = readings;
  }
  WriteEvents(fd, seconds, &times, &mutex);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  Figures f;
  size_t n = 0;
  {
    std::lock_guard lock(mutex);
    f = Summarise(latencies, seconds);
    n = readings - before;
  }
  const double rss = RssMb(daemon.pid());
  ::close(fd);
  client.Stop();
  io.Stop();
  daemon.Stop();
  std::filesystem::remove(fifo);
  std::printf(
      "%-9s %8.1f/s   event write -> subscriber p50 %6.3f ms  p99 %6.3f ms   (%zu changes)   "
      "baseline bare FIFO read p50 %6.3f ms p99 %6.3f ms   RSS %5.1f MB\n",
      "gamepad", static_cast<double>(n) / seconds, f.p50_ms, f.p99_ms, f.n, baseline.p50_ms,
      baseline.p99_ms, rss);
}

int RunBenchmark(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 5.0;
  if (!std::getenv("IGMS_BIN_DIR")) {
    const auto bin =
        std::filesystem::canonical("/proc/self/exe").parent_path().parent_path() / "bin";
    setenv("IGMS_BIN_DIR", bin.c_str(), 1);
  }
  std::printf("device daemons, %.0f s each, simulators paced at 9600 baud on pseudo-terminals\n",
              seconds);

  auto flybox = std::make_unique<FlyBoxSim>();
  flybox->OnInput(cerealbox::ConfigCommand(cerealbox::kFlyBoxLayout), 0);
  const Figures joy_base =
      Baseline(std::move(flybox), "", "p", 50, cerealbox::kFlyBoxLayout.report_length(), seconds);
  RunDevice<igms::devices::JoystickState>("joystick", "igms-joystickd", {},
                                          std::make_unique<FlyBoxSim>(),
                                          "igms.devices.JoystickService.Live", seconds, joy_base);

  const Figures viewer_base =
      Baseline(std::make_unique<ViewerSim>(), "", "P", 70, boom::kReportLength, seconds);
  RunDevice<igms::devices::ViewerState>("viewer", "igms-viewerd", {"--poll-hz", "70"},
                                        std::make_unique<ViewerSim>(),
                                        "igms.devices.ViewerService.Live", seconds, viewer_base);

  RunDevice<igms::devices::ViewerState>("viewer-S", "igms-viewerd", {"--stream"},
                                        std::make_unique<ViewerSim>(),
                                        "igms.devices.ViewerService.Live", seconds, viewer_base);

  const Figures platform_base =
      Baseline(std::make_unique<MollySim>(), "", molly::EncodeQuery(), 50, 9, seconds);
  RunDevice<igms::devices::PlatformState>(
      "platform", "igms-platformd", {}, std::make_unique<MollySim>(),
      "igms.devices.PlatformService.Live", seconds, platform_base);

  // The thesis's testbed, as igms-rangerd ranges it by default.
  RangerSimOptions testbed;
  testbed.world = TestbedRangerWorld();
  const Figures ranger_base =
      Baseline(std::make_unique<RangerSim>(testbed), "", "R", 6, 5, seconds);
  RunDevice<igms::devices::RangerState>("ranger", "igms-rangerd", {"--poll-hz", "6"},
                                        std::make_unique<RangerSim>(testbed),
                                        "igms.devices.RangerService.Live", seconds, ranger_base);

  RunGamepad(seconds);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return igms::bench::MainReportingFailures(argc, argv, RunBenchmark);
}
