// Server and client sessions on real loopback sockets.
#include <gtest/gtest.h>

#include <atomic>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/write.hpp>
#include <thread>
#include <utility>
#include <vector>

#include "common/net/client.h"
#include "common/net/framing.h"
#include "common/net/mailbox.h"
#include "common/net/server.h"
#include "tests/support/io_thread.h"
#include "tests/support/wait.h"

namespace igms::net {
namespace {

using namespace std::chrono_literals;
using Msg = igms::PingResponse;  // a handy message for streams: uptime_ms carries a counter
const std::string kEcho = "test.Echo";
const std::string kSilent = "test.NeverAnswers";
const std::string kCount = "test.Count";

using igms::testing::IoThread;

// A server with an echo method, a method that never answers and a counting stream that
// publishes `count` messages of `bytes` each from a worker thread.
struct TestServer {
  explicit TestServer(boost::asio::io_context& io, ServerOptions o = {})
      : server(io, std::move(o)) {
    server.Handle<igms::Envelope, igms::Envelope>(
        kEcho, [](const igms::Envelope& req, igms::Envelope& resp) {
          resp = req;
          return Status::Ok();
        });
    server.HandleAsync<igms::Envelope, igms::Envelope>(
        kSilent, [this](const igms::Envelope&, Reply<igms::Envelope> reply) {
          std::lock_guard lock(mutex);
          held.push_back(reply);  // never called
        });
    server.HandleStream<igms::Envelope, Msg>(
        kCount,
        [this](const igms::Envelope& req, const std::shared_ptr<Publisher<Msg>>& pub) {
          const int count = req.header().correlation_id() == 0
                                ? 1000000
                                : static_cast<int>(req.header().correlation_id());
          const std::string blob(req.payload().size(), 'b');
          std::lock_guard lock(mutex);
          workers.emplace_back([pub, count, blob, this] {
            for (int i = 1; i <= count && !pub->closed() && !stop; ++i) {
              Msg m;
              m.set_uptime_ms(i);
              m.set_program(blob);
              pub->Send(m);
              std::this_thread::sleep_for(1ms);
            }
          });
          return Status::Ok();
        },
        /*latest_only=*/false);
    server.Start();
  }
  ~TestServer() {
    stop = true;
    server.Stop();
    for (auto& t : workers) t.join();
  }
  Server server;
  std::mutex mutex;
  std::vector<Reply<igms::Envelope>> held;
  std::vector<std::thread> workers;
  std::atomic<bool> stop{false};
};

ClientOptions To(const TestServer& s) {
  ClientOptions o;
  o.port = s.server.port();
  o.connect_timeout = 1000ms;
  return o;
}

igms::Envelope EchoRequest(const std::string& text) {
  igms::Envelope e;
  e.set_kind(igms::Envelope::REQUEST);
  e.set_method(text);
  return e;
}

TEST(Sessions, PingAndEcho) {
  IoThread io;
  ServerOptions o;
  o.name = "echo";
  TestServer server(io.io(), o);
  Client client(io.io(), To(server));
  client.Start();
  auto ping = client.CallSync<igms::PingResponse>("igms.Server.Ping", igms::PingRequest(), 2s);
  ASSERT_TRUE(ping.ok()) << ping.status.ToString();
  EXPECT_EQ(ping.value.server_name(), "echo");
  auto echo = client.CallSync<igms::Envelope>(kEcho, EchoRequest("hello"), 2s);
  ASSERT_TRUE(echo.ok()) << echo.status.ToString();
  EXPECT_EQ(echo.value.method(), "hello");
}

TEST(Sessions, UnknownMethodIsAnErrorAndTheSessionGoesOn) {
  IoThread io;
  TestServer server(io.io());
  Client client(io.io(), To(server));
  client.Start();
  auto r = client.CallSync<igms::Envelope>("no.Such", EchoRequest("x"), 2s);
  EXPECT_EQ(r.status.code, igms::UNKNOWN_METHOD);
  EXPECT_TRUE(client.CallSync<igms::Envelope>(kEcho, EchoRequest("y"), 2s).ok());
}

TEST(Sessions, HundredConcurrentClients) {
  IoThread io(2);
  TestServer server(io.io());
  std::vector<std::unique_ptr<Client>> clients;
  for (int i = 0; i < 100; ++i) {
    clients.push_back(std::make_unique<Client>(io.io(), To(server)));
    clients.back()->Start();
  }
  std::atomic<int> good{0};
  std::vector<std::thread> callers;
  callers.reserve(100);
  for (int i = 0; i < 100; ++i) {
    callers.emplace_back([&, i] {
      for (int k = 0; k < 20; ++k) {
        const std::string text = std::to_string(i) + "/" + std::to_string(k);
        auto r = clients[i]->CallSync<igms::Envelope>(kEcho, EchoRequest(text), 5s);
        if (r.ok() && r.value.method() == text) ++good;
      }
    });
  }
  for (auto& t : callers) t.join();
  EXPECT_EQ(good.load(), 2000);
  EXPECT_EQ(server.server.session_count(), 100u);
}

// One client shared by many threads, small and large requests mixed, so calls written from
// the callers' threads interleave with frames queued behind a large write in flight; every
// answer must match its request.
TEST(Sessions, ManyThreadsShareOneClient) {
  IoThread io(2);
  ServerOptions so;
  so.max_frame_bytes = 16u << 20;
  TestServer server(io.io(), so);
  ClientOptions co = To(server);
  co.max_frame_bytes = 16u << 20;
  Client client(io.io(), co);
  client.Start();
  ASSERT_TRUE(client.WaitConnected(5s));
  std::atomic<int> good{0};
  std::vector<std::thread> callers;
  callers.reserve(8);
  for (int i = 0; i < 8; ++i) {
    callers.emplace_back([&, i] {
      for (int k = 0; k < 50; ++k) {
        igms::Envelope req = EchoRequest(std::to_string(i) + "/" + std::to_string(k));
        if ((i + k) % 7 == 0) req.set_payload(std::string(1u << 20, static_cast<char>('a' + i)));
        auto r = client.CallSync<igms::Envelope>(kEcho, req, 10s);
        if (r.ok() && r.value.method() == req.method() && r.value.payload() == req.payload()) {
          ++good;
        }
      }
    });
  }
  for (auto& t : callers) t.join();
  EXPECT_EQ(good.load(), 400);
}

TEST(Sessions, RequestTimesOut) {
  IoThread io;
  TestServer server(io.io());
  Client client(io.io(), To(server));
  client.Start();
  const auto t0 = std::chrono::steady_clock::now();
  auto r = client.CallSync<igms::Envelope>(kSilent, EchoRequest("x"), 200ms);
  const auto took = std::chrono::steady_clock::now() - t0;
  EXPECT_EQ(r.status.code, igms::TIMEOUT) << r.status.ToString();
  EXPECT_GE(took, 190ms);
  EXPECT_LT(took, 2s);
}

TEST(Sessions, CallToAbsentServerTimesOutWithAClearMessage) {
  IoThread io;
  ClientOptions o;
  {
    // A port nobody listens on: bind one, note it, close it.
    boost::asio::ip::tcp::acceptor a(io.io(), {boost::asio::ip::make_address("127.0.0.1"), 0});
    o.port = a.local_endpoint().port();
  }
  Client client(io.io(), o);
  client.Start();
  auto r = client.CallSync<igms::PingResponse>("igms.Server.Ping", igms::PingRequest(), 300ms);
  EXPECT_EQ(r.status.code, igms::TIMEOUT);
  EXPECT_NE(r.status.message.find("no connection"), std::string::npos) << r.status.message;
}

TEST(Sessions, ClientThatStopsReadingDoesNotStallOthers) {
  IoThread io(2);
  ServerOptions o;
  o.max_write_queue_bytes = 8u << 20;
  TestServer server(io.io(), o);

  // A raw peer subscribes to a stream of 256 KiB messages and then never reads.
  boost::asio::io_context raw_io;
  boost::asio::ip::tcp::socket raw(raw_io);
  raw.connect({boost::asio::ip::make_address("127.0.0.1"), server.server.port()});
  igms::Envelope sub;
  sub.set_kind(igms::Envelope::SUBSCRIBE);
  sub.set_method(kCount);
  igms::Envelope req;
  req.set_payload(std::string(std::size_t{256} * 1024, 'p'));
  sub.set_payload(req.SerializeAsString());
  sub.mutable_header()->set_correlation_id(1);
  boost::asio::write(raw, boost::asio::buffer(EncodeFrame(sub)));

  Client client(io.io(), To(server));
  client.Start();
  ASSERT_TRUE(client.WaitConnected(2s));
  // Time for the stuck peer's queue to fill; the calls below must be served however full it is.
  std::this_thread::sleep_for(300ms);
  for (int i = 0; i < 50; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    auto r = client.CallSync<igms::Envelope>(kEcho, EchoRequest("ok"), 2s);
    ASSERT_TRUE(r.ok()) << r.status.ToString();
    EXPECT_LT(std::chrono::steady_clock::now() - t0, 1s);
  }
  // The stuck peer is eventually disconnected: its queue passed the limit.
  EXPECT_TRUE(igms::testing::WaitUntil([&] { return server.server.session_count() <= 1; }, 5s));
  EXPECT_EQ(server.server.session_count(), 1u);
}

TEST(Sessions, ShutdownWithClientsConnected) {
  IoThread io;
  auto server = std::make_unique<TestServer>(io.io());
  std::vector<std::unique_ptr<Client>> clients;
  for (int i = 0; i < 10; ++i) {
    auto o = To(*server);
    o.reconnect = false;
    clients.push_back(std::make_unique<Client>(io.io(), o));
    clients.back()->Start();
    ASSERT_TRUE(clients.back()->WaitConnected(2s));
  }
  server->server.Stop();
  for (auto& c : clients) {
    EXPECT_TRUE(igms::testing::WaitUntil([&] { return !c->connected(); }, 5s));
  }
  EXPECT_EQ(server->server.session_count(), 0u);
  auto r = clients[0]->CallSync<igms::Envelope>(kEcho, EchoRequest("late"), 500ms);
  EXPECT_FALSE(r.ok());
}

TEST(Sessions, ReconnectsAndResubscribesAfterServerRestart) {
  IoThread io;
  auto server = std::make_unique<TestServer>(io.io());
  const auto port = server->server.port();
  Client client(io.io(), To(*server));
  Mailbox<int> received(100000);
  igms::Envelope req;
  req.mutable_header()->set_correlation_id(100000);
  client.Subscribe<Msg>(kCount, req,
                        [&](const Msg& m) { received.Push(static_cast<int>(m.uptime_ms())); });
  client.Start();
  auto wait_for = [&](int n) {
    return igms::testing::WaitUntil([&] { return static_cast<int>(received.size()) >= n; }, 5s);
  };
  ASSERT_TRUE(wait_for(5));
  server.reset();  // the server goes away
  while (received.TryPop()) {
  }
  ServerOptions o;
  o.port = port;
  server = std::make_unique<TestServer>(io.io(), o);  // and comes back on the same port
  ASSERT_TRUE(wait_for(5)) << "no stream messages after the restart";
  auto first = received.TryPop();
  ASSERT_TRUE(first);
  EXPECT_LT(*first, 100) << "the stream restarted from its beginning on the new server";
  EXPECT_TRUE(client.CallSync<igms::Envelope>(kEcho, EchoRequest("back"), 2s).ok());
}

TEST(Sessions, TokenAcceptedAndRejected) {
  IoThread io;
  ServerOptions o;
  o.token = "s3cret";
  TestServer server(io.io(), o);
  auto good = To(server);
  good.token = "s3cret";
  Client ok(io.io(), good);
  ok.Start();
  EXPECT_TRUE(ok.CallSync<igms::Envelope>(kEcho, EchoRequest("in"), 2s).ok());

  auto bad = To(server);
  bad.token = "guess";
  bad.reconnect = false;
  Client rejected(io.io(), bad);
  rejected.Start();
  auto r = rejected.CallSync<igms::Envelope>(kEcho, EchoRequest("in"), 2s);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.status.ToString().find("UNAUTHENTICATED"), std::string::npos) << r.status.ToString();

  // A peer that sends no HELLO at all is not served either.
  boost::asio::io_context raw_io;
  boost::asio::ip::tcp::socket raw(raw_io);
  raw.connect({boost::asio::ip::make_address("127.0.0.1"), server.server.port()});
  igms::Envelope e = EchoRequest("sneak");
  e.set_method(kEcho);
  boost::asio::write(raw, boost::asio::buffer(EncodeFrame(e)));
  std::string in(4096, '\0');
  boost::system::error_code ec;
  std::size_t n = raw.read_some(boost::asio::buffer(in), ec);
  ASSERT_FALSE(ec);
  DecodeResult d = DecodeFrame(std::string_view(in.data(), n), kDefaultMaxFrameBytes);
  ASSERT_EQ(d.status, DecodeStatus::kFrame);
  igms::Envelope answer;
  std::string error;
  ASSERT_TRUE(ParseEnvelope(d.frame, &answer, &error));
  EXPECT_EQ(answer.kind(), igms::Envelope::ERROR);
  EXPECT_EQ(answer.error().code(), igms::UNAUTHENTICATED);
  // The read blocks until the server closes the connection (or sends more, which it must not).
  raw.read_some(boost::asio::buffer(in), ec);
  EXPECT_TRUE(ec) << "the unauthenticated peer should be disconnected";
  EXPECT_TRUE(ok.CallSync<igms::Envelope>(kEcho, EchoRequest("still"), 2s).ok());
}

TEST(Sessions, OversizeAndGarbageFramesCloseOnlyThatConnection) {
  IoThread io;
  ServerOptions o;
  o.max_frame_bytes = 1024;
  TestServer server(io.io(), o);
  Client client(io.io(), To(server));
  client.Start();
  ASSERT_TRUE(client.CallSync<igms::Envelope>(kEcho, EchoRequest("a"), 2s).ok());
  for (const std::string& bad : {EncodeFrame(EchoRequest(std::string(5000, 'x'))),
                                 std::string("\x05hello", 6), std::string(8, '\xff')}) {
    boost::asio::io_context raw_io;
    boost::asio::ip::tcp::socket raw(raw_io);
    raw.connect({boost::asio::ip::make_address("127.0.0.1"), server.server.port()});
    boost::system::error_code ec;
    boost::asio::write(raw, boost::asio::buffer(bad), ec);
    std::string in(64, '\0');
    raw.read_some(boost::asio::buffer(in), ec);  // the server closes it
    EXPECT_TRUE(ec);
  }
  EXPECT_TRUE(client.CallSync<igms::Envelope>(kEcho, EchoRequest("b"), 2s).ok());
}

TEST(Sessions, IdleSessionIsClosed) {
  IoThread io;
  ServerOptions o;
  o.idle_timeout = 200ms;
  TestServer server(io.io(), o);
  boost::asio::io_context raw_io;
  boost::asio::ip::tcp::socket raw(raw_io);
  raw.connect({boost::asio::ip::make_address("127.0.0.1"), server.server.port()});
  std::string in(64, '\0');
  boost::system::error_code ec;
  const auto t0 = std::chrono::steady_clock::now();
  raw.read_some(boost::asio::buffer(in), ec);
  EXPECT_TRUE(ec);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 3s);
  // A client with heartbeats faster than the timeout stays connected.
  auto co = To(server);
  co.heartbeat_interval = 50ms;
  Client client(io.io(), co);
  client.Start();
  ASSERT_TRUE(client.WaitConnected(2s));
  std::this_thread::sleep_for(600ms);
  EXPECT_TRUE(client.CallSync<igms::Envelope>(kEcho, EchoRequest("alive"), 2s).ok());
}

TEST(Sessions, LatestOnlyStreamKeepsNoBacklog) {
  IoThread io;
  Server server(io.io(), {});
  std::shared_ptr<Publisher<Msg>> publisher;
  std::mutex m;
  server.HandleStream<igms::Envelope, Msg>(
      "test.Latest",
      [&](const igms::Envelope&, std::shared_ptr<Publisher<Msg>> p) {
        std::lock_guard lock(m);
        publisher = std::move(p);
        return Status::Ok();
      },
      /*latest_only=*/true);
  server.Start();
  ClientOptions o;
  o.port = server.port();
  Client client(io.io(), o);
  std::atomic<int> seen{0};
  std::atomic<int> last{0};
  client.Subscribe<Msg>("test.Latest", igms::Envelope(), [&](const Msg& msg) {
    ++seen;
    last = static_cast<int>(msg.uptime_ms());
  });
  client.Start();
  // The publisher is set on the server's io thread: read it under the lock.
  std::shared_ptr<Publisher<Msg>> published;
  ASSERT_TRUE(igms::testing::WaitUntil(
      [&] {
        std::lock_guard lock(m);
        published = publisher;
        return published != nullptr;
      },
      5s));
  // Publish a burst of 1 MiB frames far faster than they can be written.
  Msg msg;
  msg.set_program(std::string(1 << 20, 'f'));
  for (int i = 1; i <= 200; ++i) {
    msg.set_uptime_ms(i);
    published->Send(msg);
  }
  EXPECT_TRUE(igms::testing::WaitUntil([&] { return last == 200; }, 5s));
  EXPECT_EQ(last.load(), 200) << "the newest frame must arrive";
  EXPECT_LT(seen.load(), 200) << "older unwritten frames are replaced, not queued";
  server.Stop();
}

}  // namespace
}  // namespace igms::net
