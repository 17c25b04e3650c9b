// TLS against plain TCP, both through the network library, in the same run and in
// alternating blocks (docs/security.md):
//  - round trip of a small request (p50, p99),
//  - throughput of 500 KB requests with 8 in flight,
//  - a live 1280x1024 8-bit stream published at 60 frames/s (latest only): frames received,
//  - connection time (TCP connect, and with TLS the handshake with both certificates).
// Goals: round trip within 1.3x of plain, throughput at least 80% of plain, 60 frames/s.
// For the throughput it also prints the processor time both ends spend per MB, and
// AES-128-GCM's speed on one core here: plain's cost plus encrypting and decrypting every
// byte once is the least TLS can cost when both ends share this machine's cores, and so
// bounds the TLS/plain ratio one machine can show (docs/security.md).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <iostream>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>
// After <utility>: Boost 1.74's awaitable.hpp uses std::exchange without including it.
#include <openssl/evp.h>
#include <spdlog/spdlog.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <boost/asio.hpp>
#include <filesystem>

#include "bench/bench_main.h"
#include "common/certs/certs.h"
#include "common/config/process_options.h"
#include "common/net/client.h"
#include "common/net/server.h"
#include "common/stats/percentile.h"

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

namespace {

std::string g_certs;  // the bench's own lab authority and certificates

igms::net::TlsOptions Tls(bool on, const std::string& name) {
  return on ? igms::net::TlsOptions::FromFolder(g_certs, name) : igms::net::TlsOptions{};
}

// A server and a client, each on its own io thread, plain or TLS.
class Pair {
 public:
  explicit Pair(bool tls)
      : tls_(tls),
        server_work_(asio::make_work_guard(server_io_)),
        client_work_(asio::make_work_guard(client_io_)),
        server_(server_io_, [tls] {
          igms::net::ServerOptions so;
          so.name = "video";
          so.max_frame_bytes = 16u << 20;
          so.tls = Tls(tls, "video");
          return so;
        }()) {
    server_.Handle<igms::Envelope, igms::Envelope>("bench.Reply",
                                                   [](const igms::Envelope&, igms::Envelope& resp) {
                                                     resp.set_method("ok");
                                                     return igms::net::Status::Ok();
                                                   });
    server_.HandleStream<igms::Envelope, igms::Envelope>(
        "bench.Live",
        [this](const igms::Envelope&, std::shared_ptr<igms::net::Publisher<igms::Envelope>> p) {
          std::lock_guard lock(mutex_);
          publisher_ = std::move(p);
          return igms::net::Status::Ok();
        },
        /*latest_only=*/true);
    server_.Start();
    server_thread_ = std::thread([this] { server_io_.run(); });
    client_thread_ = std::thread([this] { client_io_.run(); });
    client_ = Connect();
  }
  ~Pair() {
    stop_ = true;
    if (publisher_thread_.joinable()) publisher_thread_.join();
    client_->Stop();
    server_.Stop();
    server_work_.reset();
    client_work_.reset();
    server_io_.stop();
    client_io_.stop();
    server_thread_.join();
    client_thread_.join();
  }
  std::unique_ptr<igms::net::Client> Connect() {
    igms::net::ClientOptions co;
    co.port = server_.port();
    co.max_frame_bytes = 16u << 20;
    co.tls = Tls(tls_, "control");
    auto c = std::make_unique<igms::net::Client>(client_io_, co);
    c->Start();
    if (!c->WaitConnected(60s)) {  // long: under valgrind on a busy machine
      std::cerr << "bench: cannot connect\n";
      std::exit(1);
    }
    return c;
  }
  igms::net::Client& client() { return *client_; }

  // Frames of a 1280x1024 camera published at `fps` for `seconds`; frames received.
  double LiveFps(int fps, double seconds) {
    std::atomic<int> received{0};
    igms::Envelope req;
    const auto id = client_->Subscribe<igms::Envelope>("bench.Live", req,
                                                       [&](const igms::Envelope&) { ++received; });
    while (true) {
      std::lock_guard lock(mutex_);
      if (publisher_) break;
    }
    igms::Envelope frame;
    frame.set_payload(std::string(std::size_t{1280} * 1024, 'p'));
    const auto start = Clock::now();
    const auto period = std::chrono::nanoseconds(1000000000 / fps);
    int sent = 0;
    for (auto next = start; Clock::now() - start < std::chrono::duration<double>(seconds);
         next += period) {
      std::this_thread::sleep_until(next);
      std::lock_guard lock(mutex_);
      publisher_->Send(frame);
      ++sent;
    }
    std::this_thread::sleep_for(100ms);  // the last frame's way
    client_->Unsubscribe(id);
    const double s = std::chrono::duration<double>(Clock::now() - start).count() - 0.1;
    return received.load() / s;
  }

 private:
  bool tls_;
  asio::io_context server_io_, client_io_;
  asio::executor_work_guard<asio::io_context::executor_type> server_work_, client_work_;
  igms::net::Server server_;
  std::unique_ptr<igms::net::Client> client_;
  std::thread server_thread_, client_thread_, publisher_thread_;
  std::mutex mutex_;
  std::shared_ptr<igms::net::Publisher<igms::Envelope>> publisher_;
  std::atomic<bool> stop_{false};
};

std::vector<double> RoundTrips(Pair& pair, int n) {
  igms::Envelope req;
  req.set_payload("ping");
  std::vector<double> us;
  for (int i = 0; i < n + 20; ++i) {
    const auto t0 = Clock::now();
    auto r = pair.client().CallSync<igms::Envelope>("bench.Reply", req, 5s);
    if (!r.ok()) {
      std::cerr << "bench: " << r.status.ToString() << "\n";
      std::exit(1);
    }
    if (i >= 20) us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
  return us;
}

double PipelinedMBps(Pair& pair, std::size_t size, int n, int window) {
  igms::Envelope req;
  req.set_payload(std::string(size, 'q'));
  std::mutex m;
  std::condition_variable cv;
  int in_flight = 0, done = 0;
  const auto t0 = Clock::now();
  for (int i = 0; i < n; ++i) {
    {
      std::unique_lock lock(m);
      cv.wait(lock, [&] { return in_flight < window; });
      ++in_flight;
    }
    pair.client().Call<igms::Envelope>("bench.Reply", req, 10s,
                                       [&](const igms::net::Result<igms::Envelope>& r) {
                                         if (!r.ok()) {
                                           std::cerr << "bench: " << r.status.ToString() << "\n";
                                           std::exit(1);
                                         }
                                         std::lock_guard lock(m);
                                         --in_flight;
                                         ++done;
                                         cv.notify_all();
                                       });
  }
  std::unique_lock lock(m);
  cv.wait(lock, [&] { return done == n; });
  return static_cast<double>(size) * n / std::chrono::duration<double>(Clock::now() - t0).count() /
         1e6;
}

// Processor time of the whole process (both ends), in seconds.
double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  auto s = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) / 1e6;
  };
  return s(u.ru_utime) + s(u.ru_stime);
}

// This thread's processor time, in seconds: what AES-GCM costs whatever else the cores do.
double ThreadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) / 1e9;
}

// AES-128-GCM (TLS's first choice) sealing 16 KB records, MB per second of processor time.
double AesGcmMBps() {
  const unsigned char key[16] = {1}, iv[12] = {2};
  std::vector<unsigned char> in(16384, 'v'), out(16384 + 16);
  EVP_CIPHER_CTX* ctx = EVP_CIPHER_CTX_new();
  EVP_EncryptInit_ex(ctx, EVP_aes_128_gcm(), nullptr, key, iv);
  std::size_t bytes = 0;
  const double t0 = ThreadCpuSeconds();
  while (ThreadCpuSeconds() - t0 < 0.3) {
    for (int i = 0; i < 16; ++i) {
      int n = 0;
      EVP_EncryptInit_ex(ctx, nullptr, nullptr, nullptr, iv);
      EVP_EncryptUpdate(ctx, out.data(), &n, in.data(), static_cast<int>(in.size()));
      EVP_EncryptFinal_ex(ctx, out.data() + n, &n);
      bytes += in.size();
    }
  }
  const double s = ThreadCpuSeconds() - t0;
  EVP_CIPHER_CTX_free(ctx);
  return static_cast<double>(bytes) / s / 1e6;
}

std::vector<double> ConnectTimes(Pair& pair, int n) {
  std::vector<double> ms;
  for (int i = 0; i < n; ++i) {
    const auto t0 = Clock::now();
    auto c = pair.Connect();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    c->Stop();
  }
  return ms;
}

}  // namespace

// bench_tls [rtt] [mbps] [live] [connect] [plain|tls] [blocks=N]: the parts named (all by
// default), for profiling one of them alone.
namespace {

int RunBenchmark(int argc, char** argv) {
  igms::config::TuneAllocator();
  std::set<std::string> parts;
  int blocks = 3, first = 0, last = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "plain") {
      last = 0;
    } else if (a == "tls") {
      first = 1;
    } else if (a.rfind("blocks=", 0) == 0) {
      blocks = std::stoi(a.substr(7));
    } else {
      parts.insert(a);
    }
  }
  auto want = [&](const char* part) { return parts.empty() || parts.count(part) > 0; };
  spdlog::set_level(spdlog::level::warn);
  const std::string dir = "/tmp/igms-bench-tls-" + std::to_string(::getpid());
  igms::certs::InitFolder(dir, 30);
  igms::certs::IssueOptions o;
  o.hosts = {"127.0.0.1"};
  igms::certs::IssueToFolder(dir, "video", o);
  igms::certs::IssueToFolder(dir, "control", o);
  g_certs = dir;

  std::vector<double> rtt[2], mbps[2], cpu_ms_per_mb[2], fps[2], connect[2];
  for (int b = 0; b < blocks; ++b) {
    for (int tls = first; tls <= last; ++tls) {
      Pair pair(tls == 1);
      if (want("rtt")) {
        auto r = RoundTrips(pair, 2000);
        rtt[tls].insert(rtt[tls].end(), r.begin(), r.end());
      }
      if (want("mbps")) {
        const double cpu0 = CpuSeconds();
        mbps[tls].push_back(PipelinedMBps(pair, std::size_t{500} * 1000, 200, 8));
        cpu_ms_per_mb[tls].push_back((CpuSeconds() - cpu0) * 1e3 / (500 * 1000 * 200 / 1e6));
      }
      if (want("live")) fps[tls].push_back(pair.LiveFps(60, 1.0));
      if (want("connect")) {
        auto c = ConnectTimes(pair, 20);
        connect[tls].insert(connect[tls].end(), c.begin(), c.end());
      }
    }
  }
  std::filesystem::remove_all(dir);
  using igms::stats::Median;
  using igms::stats::Percentile;
  std::printf("%-34s %12s %12s %8s\n", "", "plain", "TLS 1.3", "TLS/plain");
  auto row = [](const char* what, std::vector<double>* v, auto stat) {
    if (v[0].empty() && v[1].empty()) return;
    const double plain = v[0].empty() ? 0 : stat(v[0]), tls = v[1].empty() ? 0 : stat(v[1]);
    std::printf("%-34s %12.1f %12.1f %8.2f\n", what, plain, tls, plain > 0 ? tls / plain : 0);
  };
  auto median = [](const std::vector<double>& v) { return Median(v); };
  row("round trip p50, us", rtt, median);
  row("round trip p99, us", rtt, [](const std::vector<double>& v) { return Percentile(v, 0.99); });
  row("500 KB x 8 in flight, MB/s", mbps, median);
  row("  processor time per MB, ms", cpu_ms_per_mb, median);
  row("live 1280x1024 at 60/s, frames/s", fps, median);
  row("connect (+ handshake), ms", connect, median);
  if (!cpu_ms_per_mb[0].empty()) {
    // Every byte encrypted once and decrypted once (about as fast), on top of plain's cost.
    const double aes = AesGcmMBps();
    const double plain_ms = Median(cpu_ms_per_mb[0]);
    std::printf("%-34s %12.1f\n", "AES-128-GCM, MB per processor s", aes);
    std::printf("%-34s %12.2f\n", "TLS/plain at best, shared cores",
                plain_ms / (plain_ms + 2 * 1e3 / aes));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return igms::bench::MainReportingFailures(argc, argv, RunBenchmark);
}
