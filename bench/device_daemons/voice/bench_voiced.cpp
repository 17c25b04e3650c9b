// The voice daemon: commands a second through the whole path, the added latency from the
// simulated Dragon writing a command's last byte to a TCP subscriber receiving it (p50,
// p99; target under 2 ms), and the daemon's resident memory, with the Dragon line and with
// the recogniser loaded (the speech daemon is exempt from the 30 MB target).
//
// The simulator runs here on a real pseudo-terminal paced at 9600 baud; the daemon is the
// real igms-voiced, started with --serial on it as it would be on hardware. The operator
// speaks every `period` ms, alternating "wireframe" and "solid" (valid in every state they
// leave the system in). Both clocks are CLOCK_MONOTONIC.
//
//   build/bench/bench_voiced [seconds, default 5] [period ms, default 100]
#include <algorithm>
#include <cstdio>
#include <deque>
#include <exception>
#include <filesystem>
#include <fstream>
#include <mutex>

#include "bench/bench_main.h"
#include "common/base/clock.h"
#include "common/net/client.h"
#include "common/stats/percentile.h"
#include "device_daemons/serial/pty_host.h"
#include "device_daemons/voice/dragon_sim.h"
#include "igms/devices.pb.h"
#include "tests/support/daemon_process.h"
#include "tests/support/files.h"
#include "tests/support/io_thread.h"
#include "tests/support/wait.h"

namespace {

using namespace igms;
using devices::testing::DaemonProcess;

// Forwards to the DragonSim and remembers, in output order, which chunks are commands, so
// the host's chunk-written callback can time exactly those.
class TimedDragon : public devices::SimulatedDevice {
 public:
  std::vector<std::string> OnInput(std::string_view bytes, int64_t now) override {
    return Note(sim.OnInput(bytes, now));
  }
  std::vector<std::string> Poll(int64_t now, int64_t* wake) override {
    return Note(sim.Poll(now, wake));
  }
  void Written(int64_t t) {
    std::lock_guard lock(mutex);
    if (kinds.empty()) return;
    if (kinds.front()) command_ends.push_back(t);
    kinds.pop_front();
  }
  voice::DragonSim sim;
  std::mutex mutex;
  std::deque<bool> kinds;
  std::vector<int64_t> command_ends;

 private:
  std::vector<std::string> Note(std::vector<std::string> chunks) {
    std::lock_guard lock(mutex);
    for (const auto& c : chunks) kinds.push_back(c != "00\r");
    return chunks;
  }
};

double RssMb(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string key;
  while (in >> key) {
    if (key == "VmRSS:") {
      double kb = 0;
      in >> kb;
      return kb / 1024.0;
    }
    in.ignore(1 << 12, '\n');
  }
  return 0;
}

int RunBenchmark(int argc, char** argv) {
  // The daemon is found next to this program's folder (build/bench -> build/bin).
  const std::string bin =
      (std::filesystem::absolute(argv[0]).parent_path().parent_path() / "bin").string();
  setenv("IGMS_BIN_DIR", bin.c_str(), 0);
  const double seconds = argc > 1 ? std::atof(argv[1]) : 5.0;
  const int period_ms = argc > 2 ? std::atoi(argv[2]) : 100;
  auto device = std::make_unique<TimedDragon>();
  TimedDragon* dragon = device.get();
  devices::PtyHost host(std::move(device), {igms::testing::TempPath("bench-dragon"), 9600});
  host.SetOnChunkWritten([dragon](int64_t t) { dragon->Written(t); });
  std::string error;
  if (!host.Start(&error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  DaemonProcess daemon("igms-voiced", {"--serial", host.port(), "--port", "0"});
  const uint16_t port = daemon.WaitForPort();
  if (port == 0) {
    std::fprintf(stderr, "igms-voiced did not start:\n%s\n", daemon.Log().c_str());
    return 1;
  }
  igms::testing::IoThread io;
  net::ClientOptions o;
  o.port = port;
  o.name = "bench_voiced";
  net::Client client(io.io(), o);
  client.Start();
  std::mutex mutex;
  std::vector<std::pair<uint64_t, int64_t>> received;  // sequence, receive time
  client.Subscribe<devices::VoiceState>("igms.devices.VoiceService.Live",
                                        devices::SubscribeRequest(),
                                        [&](const devices::VoiceState& s) {
                                          const int64_t now = igms::MonotonicNs();
                                          std::lock_guard lock(mutex);
                                          received.emplace_back(s.stamp().sequence(), now);
                                        });
  igms::testing::WaitUntil([&] {
    return client.connected() && client.CallSync<devices::LinkStatus>(
                                           "igms.devices.VoiceService.Status",
                                           devices::GetStatusRequest(), std::chrono::seconds(1))
                                         .value.state() == devices::CONNECTED;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const auto start = std::chrono::steady_clock::now();
  int said = 0;
  while (std::chrono::steady_clock::now() - start < std::chrono::duration<double>(seconds)) {
    host.WithDevice([&](devices::SimulatedDevice&) {
      dragon->sim.Say(said % 2 ? voice::Command::kSolid : voice::Command::kWireframe,
                      igms::MonotonicNs());
    });
    ++said;
    std::this_thread::sleep_for(std::chrono::milliseconds(period_ms));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const double rss = RssMb(daemon.pid());
  std::vector<double> latency_ms;
  size_t got = 0;
  {
    std::lock_guard lock(mutex);
    std::lock_guard lock2(dragon->mutex);
    got = received.size();
    for (const auto& [sequence, t] : received) {
      if (sequence == 0 || sequence > dragon->command_ends.size()) continue;
      latency_ms.push_back(static_cast<double>(t - dragon->command_ends[sequence - 1]) * 1e-6);
    }
  }
  client.Stop();
  io.Stop();
  daemon.Stop();
  host.Stop();
  std::printf("voice, Dragon line at 9600 baud: %d commands said, %zu received (%.1f a second)\n",
              said, got, static_cast<double>(got) / seconds);
  std::printf("  last byte -> subscriber: p50 %.2f ms, p99 %.2f ms, max %.2f ms over %zu\n",
              stats::Percentile(latency_ms, 0.5), stats::Percentile(latency_ms, 0.99),
              stats::Percentile(latency_ms, 1.0), latency_ms.size());
  std::printf("  igms-voiced resident memory: %.1f MB\n", rss);

  // The recogniser's footprint: the daemon with the model loaded, idle.
  const std::string wav = igms::testing::TempPath("bench-freeze.wav");
  if (std::system(("espeak-ng -w " + wav + " freeze").c_str()) == 0) {
    DaemonProcess recogniser("igms-voiced", {"--wav", wav, "--port", "0"});
    if (recogniser.WaitForPort(std::chrono::seconds(60)) != 0) {
      std::this_thread::sleep_for(std::chrono::seconds(2));
      std::printf("  igms-voiced with the recogniser loaded: %.1f MB\n", RssMb(recogniser.pid()));
    }
    recogniser.Stop();
    std::remove(wav.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return igms::bench::MainReportingFailures(argc, argv, RunBenchmark);
}
