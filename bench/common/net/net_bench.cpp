// The network library against raw loopback TCP, measured in the same run:
//  - round trip of a small request (p50, p99) and of a 500 KB request with a small answer,
//  - throughput of 500 KB requests,
//  - the server's resident memory per idle connected client, with 1,000 clients.
// Targets (docs/protocol.md): p50 round trip within 2x of raw, throughput >= 70% of raw,
// under 64 KB per idle client.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <utility>
#include <boost/asio.hpp>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "common/config/process_options.h"
#include "common/net/client.h"
#include "common/net/framing.h"
#include "common/net/server.h"

namespace asio = boost::asio;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

namespace {

struct Stats {
  double p50_us, p99_us, mb_per_s;
};

// Throughput from the median time: on a shared machine a few descheduled calls would
// otherwise decide the figure.
Stats Summarise(std::vector<double> us, std::size_t bytes_each) {
  std::sort(us.begin(), us.end());
  const double p50 = us[us.size() / 2];
  return {p50, us[us.size() * 99 / 100], bytes_each / p50};
}

// Raw baseline: the client writes `request` bytes, the server reads them and writes `reply`
// bytes back; blocking sockets, one thread each, TCP_NODELAY as the library sets it.
Stats RawRoundTrips(std::size_t request, std::size_t reply, int n) {
  asio::io_context io;
  tcp::acceptor acceptor(io, {asio::ip::make_address("127.0.0.1"), 0});
  std::thread server([&] {
    tcp::socket s(io);
    acceptor.accept(s);
    s.set_option(tcp::no_delay(true));
    std::string in(request, '\0'), out(reply, 'r');
    for (int i = 0; i < n; ++i) {
      asio::read(s, asio::buffer(in));
      asio::write(s, asio::buffer(out));
    }
  });
  tcp::socket c(io);
  c.connect(acceptor.local_endpoint());
  c.set_option(tcp::no_delay(true));
  std::string out(request, 'q'), in(reply, '\0');
  std::vector<double> us;
  for (int i = 0; i < n; ++i) {
    const auto t0 = Clock::now();
    asio::write(c, asio::buffer(out));
    asio::read(c, asio::buffer(in));
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
  server.join();
  return Summarise(us, request);
}

Stats LibraryRoundTrips(std::size_t request, std::size_t reply, int n) {
  asio::io_context server_io, client_io;
  auto sw = asio::make_work_guard(server_io);
  auto cw = asio::make_work_guard(client_io);
  igms::net::ServerOptions so;
  so.max_frame_bytes = 16u << 20;
  igms::net::Server server(server_io, so);
  const std::string answer(reply, 'r');
  server.Handle<igms::Envelope, igms::Envelope>(
      "bench.Echo", [&](const igms::Envelope&, igms::Envelope& resp) {
        resp.set_payload(answer);
        return igms::net::Status::Ok();
      });
  server.Start();
  std::thread st([&] { server_io.run(); });
  std::thread ct([&] { client_io.run(); });
  igms::net::ClientOptions co;
  co.port = server.port();
  co.max_frame_bytes = 16u << 20;
  igms::net::Client client(client_io, co);
  client.Start();
  client.WaitConnected(2s);
  igms::Envelope req;
  req.set_payload(std::string(request, 'q'));
  std::vector<double> us;
  for (int i = 0; i < n + 10; ++i) {
    const auto t0 = Clock::now();
    auto r = client.CallSync<igms::Envelope>("bench.Echo", req, 5s);
    if (!r.ok()) {
      std::cerr << "bench: " << r.status.ToString() << "\n";
      std::exit(1);
    }
    if (i >= 10) us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
  client.Stop();
  server.Stop();
  sw.reset();
  cw.reset();
  server_io.stop();
  client_io.stop();
  st.join();
  ct.join();
  return Summarise(us, request);
}

long RssKb(pid_t pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(f, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;
}

void RaiseFileLimit(rlim_t want) {
  rlimit r{};
  getrlimit(RLIMIT_NOFILE, &r);
  r.rlim_cur = std::min(want, r.rlim_max);
  setrlimit(RLIMIT_NOFILE, &r);
}

// A server in a child process; 1,000 clients connect from here, each sends HELLO and idles.
void IdleClientMemory(int clients) {
  RaiseFileLimit(clients + 256);
  int pipefd[2];
  if (pipe(pipefd) != 0) return;
  std::fflush(stdout);
  const pid_t child = fork();
  if (child == 0) {
    asio::io_context io;
    igms::net::Server server(io, {});
    server.Start();
    const std::uint16_t port = server.port();
    if (write(pipefd[1], &port, sizeof port) != sizeof port) _exit(1);
    io.run();
    _exit(0);
  }
  std::uint16_t port = 0;
  if (read(pipefd[0], &port, sizeof port) != sizeof port) return;
  std::this_thread::sleep_for(200ms);
  const long before = RssKb(child);
  asio::io_context io;
  std::vector<tcp::socket> sockets;
  igms::Envelope hello;
  hello.set_kind(igms::Envelope::HELLO);
  hello.mutable_header()->set_protocol_version(1);
  const std::string frame = igms::net::EncodeFrame(hello);
  for (int i = 0; i < clients; ++i) {
    sockets.emplace_back(io);
    sockets.back().connect({asio::ip::make_address("127.0.0.1"), port});
    asio::write(sockets.back(), asio::buffer(frame));
  }
  std::this_thread::sleep_for(500ms);
  const long after = RssKb(child);
  std::printf("idle clients: %d connected, server RSS %ld KB -> %ld KB: %.1f KB per client (target < 64)\n",
              clients, before, after, double(after - before) / clients);
  sockets.clear();
  kill(child, SIGTERM);
  waitpid(child, nullptr, 0);
}

}  // namespace

int main() {
  igms::config::TuneAllocator();
  std::printf("IGMS network library vs raw loopback TCP (same run)\n");
  const Stats raw_small = RawRoundTrips(100, 100, 5000);
  const Stats lib_small = LibraryRoundTrips(100, 100, 5000);
  std::printf("small round trip   raw p50 %.1f us p99 %.1f us | igms p50 %.1f us p99 %.1f us | p50 ratio %.2fx (target <= 2x)\n",
              raw_small.p50_us, raw_small.p99_us, lib_small.p50_us, lib_small.p99_us,
              lib_small.p50_us / raw_small.p50_us);
  const Stats raw_big = RawRoundTrips(500000, 100, 1000);
  const Stats lib_big = LibraryRoundTrips(500000, 100, 1000);
  std::printf("500 KB requests    raw p50 %.1f us %.0f MB/s | igms p50 %.1f us %.0f MB/s | throughput %.0f%% of raw (target >= 70%%)\n",
              raw_big.p50_us, raw_big.mb_per_s, lib_big.p50_us, lib_big.mb_per_s,
              100.0 * lib_big.mb_per_s / raw_big.mb_per_s);
  IdleClientMemory(1000);
  return 0;
}
