// Request to first audio sample: how long after a client sends Play does the sound's first
// sample come out, measured on what OpenAL's wave output captured.
//
// The wave writer mixes in real time, one period at a time, and its file grows as it mixes.
// A thread watches the file's size: every growth to F frames at time t says the writer had
// mixed F frames by t, so the capture's frame 0 lies at or before t - F / rate; the earliest
// such bound over the run places frame n at t0 + n / rate. Each play's first sample is found
// in the capture by lining up the source clip. The writer mixes a period of P frames once
// that much real time has passed, so frame n leaves the mixer at t0 + (n + P) / rate (the
// end of its period): the latency is that moment minus the one the request was sent. It
// includes waiting for the next period, as a sound card would; it excludes a card's own
// output buffer, which the wave writer does not have.
//
// On a loaded machine the writer sometimes wakes late and mixes several periods at once; a
// sound started then lands in a period whose nominal end has already passed, and its
// figure comes out below the period, even negative (the minimum column shows it). The
// median and the 99th percentile are not moved by these few.
//
// Baseline in the same run: the same measure on an engine in this process (no network,
// no server), at the same period. Then the server over loopback TCP at the same period,
// and at a short period.
//
//   bench_sound_latency [--plays N] [--key woodblock]
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

#include "bench/bench_main.h"
#include "common/stats/percentile.h"
#include "sound_server/audio_file.h"
#include "sound_server/engine.h"
#include "sound_server/wave_capture.h"
#include "tests/support/sound_bank.h"
#include "tests/support/sound_server_process.h"

namespace igms::sound {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

double Seconds(Clock::time_point t) {
  return std::chrono::duration<double>(t.time_since_epoch()).count();
}

// Watches a growing capture file and keeps the earliest bound on when its frame 0 played.
class CaptureClock {
 public:
  explicit CaptureClock(std::filesystem::path wave, int rate)
      : wave_(std::move(wave)), rate_(rate) {
    thread_ = std::thread([this] { Run(); });
  }
  ~CaptureClock() {
    stop_ = true;
    thread_.join();
  }
  double FrameZero() const {
    std::lock_guard lock(mutex_);
    return frame_zero_;
  }

 private:
  void Run() {
    int64_t last = -1;
    while (!stop_) {
      const int64_t frames = CapturedFrames(wave_);
      const double now = Seconds(Clock::now());
      if (frames > 0 && frames != last) {
        last = frames;
        std::lock_guard lock(mutex_);
        frame_zero_ = std::min(frame_zero_, now - double(frames) / rate_);
      }
      std::this_thread::sleep_for(100us);
    }
  }
  std::filesystem::path wave_;
  int rate_;
  std::atomic<bool> stop_{false};
  mutable std::mutex mutex_;
  double frame_zero_ = 1e300;
  std::thread thread_;
};

struct Run {
  std::string name;
  std::vector<double> latencies_ms;
  int missing = 0;
};

// Plays `plays` times through `play` (which returns false on failure), waiting for the end
// and a gap each time; then finds each play in the capture.
Run Measure(const std::string& name, const std::filesystem::path& wave, int rate, int period,
            const AudioClip& clip, int plays, const std::function<bool()>& play,
            const std::function<void()>& wait_idle, const std::function<void()>& finish) {
  Run run{name, {}, 0};
  std::vector<double> sent;
  {
    CaptureClock clock(wave, rate);
    std::this_thread::sleep_for(300ms);  // a few growths of the file before the first play
    for (int i = 0; i < plays; ++i) {
      // Randomise the phase against the mixing period.
      std::this_thread::sleep_for(std::chrono::microseconds(150000 + (i * 7919) % 20000));
      const double t = Seconds(Clock::now());
      if (!play()) {
        ++run.missing;
        continue;
      }
      sent.push_back(t);
      wait_idle();
    }
    std::this_thread::sleep_for(300ms);
    const double zero = clock.FrameZero();
    finish();
    std::optional<Capture> capture = ReadCapture(wave);
    if (!capture) {
      run.missing += static_cast<int>(sent.size());
      return run;
    }
    const int64_t window = static_cast<int64_t>(0.2 * rate);
    for (double t : sent) {
      const int64_t expected = static_cast<int64_t>((t - zero) * rate);
      Alignment a =
          AlignClip(capture->samples, clip.samples, expected - window / 4, expected + window, 1024);
      if (a.correlation < 0.9) {
        ++run.missing;
        continue;
      }
      run.latencies_ms.push_back((zero + double(a.offset + period) / rate - t) * 1000.0);
    }
  }
  return run;
}

using stats::Percentile;

void Print(const Run& run) {
  std::printf("%-44s %5zu %8.2f %8.2f %8.2f %8.2f %7d\n", run.name.c_str(), run.latencies_ms.size(),
              Percentile(run.latencies_ms, 0.0), Percentile(run.latencies_ms, 0.5),
              Percentile(run.latencies_ms, 0.99), Percentile(run.latencies_ms, 1.0), run.missing);
}

Run ServerRun(const std::string& key, const AudioClip& clip, int plays, int period) {
  const std::filesystem::path dir =
      igms::testing::FreshTempDir("bench-server-" + std::to_string(period));
  const std::filesystem::path wave = dir / "capture.wav";
  testing::ServerProcess server({"--output", "wave", "--wave-file", wave.string(), "--wave-rate",
                                 std::to_string(clip.sample_rate), "--period-frames",
                                 std::to_string(period)});
  const uint16_t port = server.WaitListening();
  if (port == 0) {
    std::fprintf(stderr, "the server did not start:\n%s\n", server.Log().c_str());
    return {"server did not start", {}, plays};
  }
  auto client = std::make_unique<testing::SoundClient>(port);
  client->Status();  // connection warm
  const std::string name = "server over TCP, period " + std::to_string(period) + " frames";
  Run run = Measure(
      name, wave, clip.sample_rate, period, clip, plays, [&] { return client->Play(key).ok(); },
      [&] { client->WaitIdle(); },
      [&] {
        client.reset();
        server.Terminate();
      });
  std::filesystem::remove_all(dir);
  return run;
}

}  // namespace
}  // namespace igms::sound

namespace {

int RunBenchmark(int argc, char** argv) {
  using namespace igms::sound;
  int plays = 100;
  std::string key = "woodblock";
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--plays") == 0) plays = std::max(1, std::atoi(argv[i + 1]));
    if (std::strcmp(argv[i], "--key") == 0) key = argv[i + 1];
  }
  const std::filesystem::path build =
      std::filesystem::canonical("/proc/self/exe").parent_path().parent_path();
  setenv("IGMS_BUILD_DIR", build.c_str(), 0);
  setenv("IGMS_BIN_DIR", (build / "bin").c_str(), 0);
  spdlog::set_level(spdlog::level::warn);

  igms::Result<Manifest> manifest = LoadManifest(testing::BankDir() / "manifest.yaml");
  if (!manifest.ok() || manifest->FindKey(key) == nullptr) {
    std::fprintf(stderr, "no bank or no sound '%s': %s\n", key.c_str(), manifest.error().c_str());
    return 1;
  }
  igms::Result<AudioClip> source = ReadAudioFile(manifest->FileOf(*manifest->FindKey(key)));
  if (!source.ok()) return 1;
  const AudioClip clip = *source;
  std::printf("request to first audio sample, '%s', %d plays a run, %d Hz wave output\n",
              key.c_str(), plays, clip.sample_rate);
  std::printf("%-44s %5s %8s %8s %8s %8s %7s\n", "run", "n", "min ms", "p50 ms", "p99 ms", "max ms",
              "missing");

  // Baseline: this process's own engine, no network, default period.
  constexpr int kPeriod = 256;
  const std::filesystem::path dir = igms::testing::FreshTempDir("bench-engine");
  const std::filesystem::path wave = dir / "capture.wav";
  OutputOptions out;
  out.output = "wave";
  out.wave_file = wave.string();
  out.wave_rate = clip.sample_rate;
  out.period_frames = kPeriod;
  OutputResult opened = OpenOutput(out);
  if (!opened.output) {
    std::fprintf(stderr, "%s\n", opened.error.c_str());
    return 1;
  }
  EngineResult created = Engine::Create(*manifest, std::move(opened.output));
  if (!created.engine) return 1;
  std::unique_ptr<Engine> engine = std::move(created.engine);
  PlayParams params;
  params.sound.key = key;
  const Run baseline = Measure(
      "baseline: engine in process, period " + std::to_string(kPeriod) + " frames", wave,
      clip.sample_rate, kPeriod, clip, plays, [&] { return engine->Play(params).outcome.ok(); },
      [&] {
        while (!engine->Idle()) std::this_thread::sleep_for(2ms);
      },
      [&] { engine.reset(); });
  Print(baseline);
  std::filesystem::remove_all(dir);
  const Run server = ServerRun(key, clip, plays, kPeriod);
  Print(server);
  Print(ServerRun(key, clip, plays, 64));
  std::printf("period %d frames = %.2f ms; server p50 over baseline p50: %+.2f ms\n", kPeriod,
              1000.0 * kPeriod / clip.sample_rate,
              Percentile(server.latencies_ms, 0.5) - Percentile(baseline.latencies_ms, 0.5));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return igms::bench::MainReportingFailures(argc, argv, RunBenchmark);
}
