// TLS sessions on real loopback sockets (docs/security.md): mutual certificates, the
// refusals a lab sees (no certificate, another authority, expired, wrong host, plain TCP
// on one side), authorisation by certificate name, the constant-time token, the failure
// limiter and reloading the certificates. The certificates are made here, in a scratch
// folder, by common/certs.
#include <gtest/gtest.h>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/write.hpp>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>

#include "common/certs/certs.h"
#include "common/net/client.h"
#include "common/net/server.h"
#include "tests/support/child_process.h"
#include "tests/support/io_thread.h"
#include "tests/support/wait_for.h"

namespace igms::net {
namespace {

using namespace std::chrono_literals;
using igms::testing::IoThread;
using igms::testing::ScratchDir;

const std::string kEcho = "test.Echo";
const std::string kMove = "igms.devices.PlatformService.SetOrientation";

// One lab authority with certificates for video (the server), control and igmsctl; a
// second authority with its own control; an expired control; a server named for a host
// nobody dials.
struct Lab {
  Lab() {
    certs::InitFolder(dir, 30);
    certs::IssueOptions o;
    o.hosts = {"127.0.0.1", "localhost"};
    for (const char* name : {"video", "control", "igmsctl"}) certs::IssueToFolder(dir, name, o);
    certs::IssueOptions expired = o;
    expired.start_offset_s = -7200;
    expired.life_s = 3600;
    certs::IssueToFolder(dir, "old", expired);
    certs::IssueOptions elsewhere;
    elsewhere.hosts = {"10.9.9.9", "far.example"};
    certs::IssueToFolder(dir, "faraway", elsewhere);
    certs::InitFolder(other, 30);
    certs::IssueToFolder(other, "control", o);
  }
  TlsOptions As(const std::string& name) const { return TlsOptions::FromFolder(dir, name); }
  TlsOptions Foreign(const std::string& name) const {
    TlsOptions t = TlsOptions::FromFolder(other, name);
    t.ca_file = certs::AuthorityCert(dir);  // it trusts our lab; our lab does not trust it
    return t;
  }
  ScratchDir scratch;
  std::string dir = scratch.File("lab");
  std::string other = scratch.File("other");
};

const Lab& TheLab() {
  static const Lab lab;
  return lab;
}

struct TlsServer {
  TlsServer(boost::asio::io_context& io, TlsOptions tls, ServerOptions o = {})
      : server(io, [&] {
          o.name = o.name == "server" ? "video" : o.name;
          o.tls = tls;
          return o;
        }()) {
    server.Handle<igms::Envelope, igms::Envelope>(
        kEcho, [](const igms::Envelope& req, igms::Envelope& resp) {
          resp = req;
          return Status::Ok();
        });
    server.Handle<igms::Envelope, igms::Envelope>(kMove,
                                                  [this](const igms::Envelope&, igms::Envelope&) {
                                                    ++moves;
                                                    return Status::Ok();
                                                  });
    server.Start();
  }
  Server server;
  std::atomic<int> moves{0};
};

ClientOptions To(const TlsServer& s, std::optional<TlsOptions> tls) {
  ClientOptions o;
  o.port = s.server.port();
  o.connect_timeout = 1000ms;
  o.reconnect = false;
  o.tls = std::move(tls);
  if (!o.tls) o.tls = TlsOptions{};  // plain, whatever the process's settings
  return o;
}

igms::Envelope Req(const std::string& text) {
  igms::Envelope e;
  e.set_method(text);
  return e;
}

Result<igms::Envelope> Echo(Client& c, const std::string& text = "hello") {
  return c.CallSync<igms::Envelope>(kEcho, Req(text), 3s);
}

TEST(Tls, MutualCertificatesCarryCallsBothWays) {
  IoThread io;
  TlsServer s(io.io(), TheLab().As("video"));
  Client client(io.io(), To(s, TheLab().As("control")));
  client.Start();
  auto r = Echo(client, std::string(300000, 'x'));  // many records, one frame
  ASSERT_TRUE(r.ok()) << r.status.ToString();
  EXPECT_EQ(r.value.method().size(), 300000u);
  for (int i = 0; i < 50; ++i) ASSERT_TRUE(Echo(client, std::to_string(i)).ok());
  EXPECT_TRUE(s.server.tls());
}

// Each refused peer fails with a reason that names the cause, and the server goes on
// serving a good client after every one.
void ExpectRefused(TlsServer& s, IoThread& io, const ClientOptions& o, const std::string& reason) {
  Client bad(io.io(), o);
  bad.Start();
  auto r = Echo(bad);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status.code, igms::UNAVAILABLE);
  EXPECT_NE(r.status.message.find(reason), std::string::npos) << r.status.message;
  Client good(io.io(), To(s, TheLab().As("control")));
  good.Start();
  auto ok = Echo(good);
  EXPECT_TRUE(ok.ok()) << ok.status.ToString();
}

TEST(Tls, RefusedPeersAreToldWhyAndTheServerServesTheOthers) {
  IoThread io;
  ServerOptions so;
  so.failures.max_failures = 100;  // this test's refusals all come from 127.0.0.1
  TlsServer s(io.io(), TheLab().As("video"), so);

  // A client with no certificate.
  TlsOptions none = TheLab().As("control");
  none.cert_file.clear();
  none.key_file.clear();
  none.cert_pem.clear();
  ExpectRefused(s, io, To(s, none), "this client has none");
  // One from another authority: the server refuses it.
  ExpectRefused(s, io, To(s, TheLab().Foreign("control")), "refused this client's certificate");
  // An expired one.
  ExpectRefused(s, io, To(s, TheLab().As("old")), "expired");
  // A server whose certificate names another host: the client refuses it.
  {
    TlsServer far(io.io(), TheLab().As("faraway"));
    Client c(io.io(), To(far, TheLab().As("control")));
    c.Start();
    auto r = Echo(c);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.status.message.find("does not name the host dialled"), std::string::npos)
        << r.status.message;
  }
  // A plain client: the server tells it, in clear, that it wants TLS.
  ExpectRefused(s, io, To(s, std::nullopt), "requires TLS");
  EXPECT_TRUE(igms::testing::WaitFor("the refused sessions closed",
                                     [&] { return s.server.session_count() == 0; }));
}

TEST(Tls, ATlsClientOfAPlainServerIsToldSo) {
  IoThread io;
  TlsServer plain(io.io(), TlsOptions{});
  Client c(io.io(), To(plain, TheLab().As("control")));
  c.Start();
  auto r = Echo(c);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status.message.find("plain TCP"), std::string::npos) << r.status.message;
  Client p(io.io(), To(plain, std::nullopt));
  p.Start();
  EXPECT_TRUE(Echo(p).ok());
}

TEST(Tls, OnlyControlMovesThePlatform) {
  IoThread io;
  TlsServer s(io.io(), TheLab().As("video"));
  Client diag(io.io(), To(s, TheLab().As("igmsctl")));
  diag.Start();
  ASSERT_TRUE(Echo(diag).ok());  // reading is allowed
  auto refused = diag.CallSync<igms::Envelope>(kMove, Req("go"), 3s);
  EXPECT_EQ(refused.status.code, igms::PERMISSION_DENIED) << refused.status.ToString();
  EXPECT_NE(refused.status.message.find("'igmsctl'"), std::string::npos);
  EXPECT_NE(refused.status.message.find("only control"), std::string::npos);
  EXPECT_TRUE(Echo(diag).ok());  // the session goes on
  Client control(io.io(), To(s, TheLab().As("control")));
  control.Start();
  auto moved = control.CallSync<igms::Envelope>(kMove, Req("go"), 3s);
  EXPECT_TRUE(moved.ok()) << moved.status.ToString();
  EXPECT_EQ(s.moves.load(), 1);
}

TEST(Tls, TheLabFileCanWidenTheTable) {
  Authorisation a = Authorisation::Default();
  EXPECT_FALSE(a.Allowed(kMove, "igmsctl"));
  EXPECT_TRUE(a.Allowed(kMove, "control"));
  EXPECT_FALSE(a.Allowed("igms.devices.SimService.Inject", "voice"));
  EXPECT_TRUE(a.Allowed("igms.video.VideoService.Grab", "object"));
  a.Set("PlatformService.*", {"control", "igmsctl"});
  EXPECT_FALSE(a.Allowed(kMove, "igmsctl"));  // the exact rule is more specific
  a.Set("PlatformService.SetOrientation", {"igmsctl"});
  EXPECT_TRUE(a.Allowed(kMove, "igmsctl"));
  EXPECT_TRUE(a.Allowed("igms.devices.PlatformService.Live", "igmsctl"));
  a.Set("*", {"control"});
  EXPECT_FALSE(a.Allowed("igms.video.VideoService.Grab", "object"));
}

TEST(Tls, TokenIsASecondFactor) {
  IoThread io;
  ServerOptions so;
  so.token = "s3cret";
  TlsServer s(io.io(), TheLab().As("video"), so);
  ClientOptions good = To(s, TheLab().As("control"));
  good.token = "s3cret";
  Client g(io.io(), good);
  g.Start();
  EXPECT_TRUE(Echo(g).ok());
  ClientOptions bad = good;
  bad.token = "s3cre";  // a prefix: equal lengths are not what makes it pass
  Client b(io.io(), bad);
  b.Start();
  auto r = Echo(b);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.status.message.find("token"), std::string::npos) << r.status.message;
}

TEST(Tls, RepeatedFailuresFromOneAddressAreRefusedForAWhile) {
  IoThread io;
  ServerOptions so;
  so.failures.max_failures = 3;
  so.failures.block = 60s;
  TlsServer s(io.io(), TheLab().As("video"), so);
  for (int i = 0; i < 3; ++i) {
    Client c(io.io(), To(s, TheLab().Foreign("control")));
    c.Start();
    EXPECT_FALSE(Echo(c).ok());
  }
  // Now even a good certificate from that address is cut off before the handshake.
  Client good(io.io(), To(s, TheLab().As("control")));
  good.Start();
  auto r = Echo(good);
  EXPECT_FALSE(r.ok());
}

// The limiter on real connections: failed handshakes and tokens from 127.0.0.1 past the
// limit, then every connection from there is closed before its handshake, the log says so
// once for the whole burst, and the address is served again once the block has passed.
TEST(Tls, BlockedAddressIsLoggedOnceAndReleasedAfterTheBlock) {
  auto log = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(5000);
  spdlog::default_logger()->sinks().push_back(log);
  struct Unhook {
    ~Unhook() { spdlog::default_logger()->sinks().pop_back(); }
  } unhook;
  auto lines = [&](const std::string& what) {
    int n = 0;
    for (const auto& line : log->last_formatted()) n += line.find(what) != std::string::npos;
    return n;
  };
  IoThread io;
  ServerOptions so;
  so.token = "s3cret";
  so.failures.max_failures = 3;
  so.failures.window = 5000ms;
  so.failures.block = 400ms;
  TlsServer s(io.io(), TheLab().As("video"), so);
  ClientOptions good = To(s, TheLab().As("control"));
  good.token = "s3cret";
  {
    Client g(io.io(), good);  // served before the burst
    g.Start();
    ASSERT_TRUE(Echo(g).ok());
  }
  // Two handshakes with another authority's certificate and one wrong token.
  for (int i = 0; i < 2; ++i) {
    Client c(io.io(), To(s, TheLab().Foreign("control")));
    c.Start();
    EXPECT_FALSE(Echo(c).ok());
  }
  ClientOptions wrong = good;
  wrong.token = "guess";
  // The block starts at the third failure, so not before this.
  const auto blocked_at = std::chrono::steady_clock::now();
  {
    Client c(io.io(), wrong);
    c.Start();
    EXPECT_FALSE(Echo(c).ok());
  }
  // Blocked: even the good certificate and token are cut off, three times, and logged once.
  for (int i = 0; i < 3; ++i) {
    Client g(io.io(), good);
    g.Start();
    auto r = Echo(g);
    EXPECT_FALSE(r.ok()) << "try " << i;
  }
  EXPECT_EQ(lines("refusing its connections"), 1);
  EXPECT_EQ(lines("failed 3 times"), 1);
  EXPECT_EQ(lines("video: refused 127.0.0.1"), 1);  // the burst's first failure; the rest quietly
  // Released once the block has passed: a good client is served again.
  bool served = false;
  ASSERT_TRUE(igms::testing::WaitFor(
      "the address to be released",
      [&] {
        Client g(io.io(), good);
        g.Start();
        served = Echo(g).ok();
        return served;
      },
      3000ms));
  const auto blocked_for = std::chrono::steady_clock::now() - blocked_at;
  EXPECT_GE(blocked_for, so.failures.block)
      << std::chrono::duration_cast<std::chrono::milliseconds>(blocked_for).count() << " ms";
  // Released afresh: one more failure is a new burst (logged), not a new block.
  {
    Client c(io.io(), wrong);
    c.Start();
    EXPECT_FALSE(Echo(c).ok());
  }
  EXPECT_EQ(lines("video: refused 127.0.0.1"), 2);
  Client g(io.io(), good);
  g.Start();
  EXPECT_TRUE(Echo(g).ok());
  EXPECT_EQ(lines("refusing its connections"), 1);
}

TEST(Tls, FailureLimiterCountsPerAddressAndForgets) {
  FailureLimiter::Options o;
  o.max_failures = 2;
  o.window = 1000ms;
  o.block = 500ms;
  FailureLimiter limiter(o);
  const auto t0 = FailureLimiter::Clock::now();
  bool announce = false;
  int failures = 0;
  EXPECT_TRUE(limiter.Fail("10.0.0.1", t0));  // the first of a burst is logged
  EXPECT_FALSE(limiter.Blocked("10.0.0.1", &announce, &failures, t0));
  EXPECT_FALSE(limiter.Fail("10.0.0.1", t0 + 10ms));  // the rest are not
  EXPECT_TRUE(limiter.Blocked("10.0.0.1", &announce, &failures, t0 + 20ms));
  EXPECT_TRUE(announce);
  EXPECT_EQ(failures, 2);
  EXPECT_TRUE(limiter.Blocked("10.0.0.1", &announce, &failures, t0 + 30ms));
  EXPECT_FALSE(announce);  // once per block
  EXPECT_FALSE(limiter.Blocked("10.0.0.2", &announce, &failures, t0 + 30ms));
  EXPECT_FALSE(limiter.Blocked("10.0.0.1", &announce, &failures, t0 + 600ms));
}

TEST(Tls, ReloadKeepsSessionsAndServesNewOnesWithTheNewCertificate) {
  IoThread io;
  ScratchDir scratch;
  const std::string dir = scratch.File("lab");
  std::filesystem::copy(TheLab().dir, dir);
  TlsServer s(io.io(), TlsOptions::FromFolder(dir, "video"));
  Client before(io.io(), To(s, TheLab().As("control")));
  before.Start();
  ASSERT_TRUE(Echo(before).ok());
  const auto old_serial = certs::ReadFile(certs::CertFile(dir, "video"));
  certs::IssueOptions o;
  o.hosts = {"127.0.0.1"};
  certs::IssueToFolder(dir, "video", o);
  ASSERT_NE(certs::ReadFile(certs::CertFile(dir, "video")), old_serial);
  EXPECT_TRUE(s.server.ReloadTls());
  EXPECT_TRUE(Echo(before).ok());  // not dropped
  Client after(io.io(), To(s, TheLab().As("control")));
  after.Start();
  EXPECT_TRUE(Echo(after).ok());
  // A folder gone bad keeps the certificate in use.
  std::filesystem::remove(certs::KeyFile(dir, "video"));
  EXPECT_FALSE(s.server.ReloadTls());
  Client later(io.io(), To(s, TheLab().As("control")));
  later.Start();
  EXPECT_TRUE(Echo(later).ok());
}

TEST(Tls, ExpiryIsWarnedAWeekAhead) {
  const auto& lab = TheLab();
  TlsContext fresh(lab.As("control"), TlsContext::Role::kClient);
  EXPECT_EQ(fresh.ExpiryWarning(std::chrono::hours(24 * 7)), "");
  EXPECT_NE(fresh.ExpiryWarning(std::chrono::hours(24 * 400)).find("expires on"),
            std::string::npos);
  TlsContext old(lab.As("old"), TlsContext::Role::kClient);
  EXPECT_NE(old.ExpiryWarning(std::chrono::hours(24 * 7)).find("expired on"), std::string::npos);
}

// A loopback relay between a client and a server that keeps every byte it passes on, both
// ways: what anyone watching the lab network would see.
class Wiretap {
 public:
  explicit Wiretap(std::uint16_t server_port)
      : acceptor_(io_, {boost::asio::ip::make_address("127.0.0.1"), 0}) {
    thread_ = std::thread([this, server_port] {
      boost::asio::ip::tcp::socket client(io_), server(io_);
      acceptor_.accept(client);
      server.connect({boost::asio::ip::make_address("127.0.0.1"), server_port});
      std::thread back([&] { Pump(server, client); });
      Pump(client, server);
      back.join();
    });
  }
  ~Wiretap() { thread_.join(); }
  std::uint16_t port() const { return acceptor_.local_endpoint().port(); }
  std::string Seen() {
    std::lock_guard lock(mutex_);
    return seen_;
  }

 private:
  void Pump(boost::asio::ip::tcp::socket& from, boost::asio::ip::tcp::socket& to) {
    char buf[65536];
    boost::system::error_code ec;
    for (;;) {
      const std::size_t n = from.read_some(boost::asio::buffer(buf), ec);
      if (ec) break;
      {
        std::lock_guard lock(mutex_);
        seen_.append(buf, n);
      }
      boost::asio::write(to, boost::asio::buffer(buf, n), ec);
      if (ec) break;
    }
    to.shutdown(boost::asio::ip::tcp::socket::shutdown_send, ec);
  }
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  std::thread thread_;
  std::mutex mutex_;
  std::string seen_;
};

// What the wiretap saw of a session carrying the token and a frame of "video".
std::string Overheard(const std::optional<TlsOptions>& server_tls,
                      const std::optional<TlsOptions>& client_tls) {
  IoThread io;
  ServerOptions so;
  so.token = "lab-token-0f3c9a";
  TlsServer s(io.io(), server_tls ? *server_tls : TlsOptions{}, so);
  std::string seen;
  {
    Wiretap tap(s.server.port());
    ClientOptions co = To(s, client_tls);
    co.port = tap.port();
    co.token = so.token;
    Client c(io.io(), co);
    c.Start();
    EXPECT_TRUE(Echo(c, std::string(200000, 'V') + "VIDEO-ROW-MARKER").ok());
    c.Stop();
    s.server.Stop();
    seen = tap.Seen();
  }
  return seen;
}

TEST(Tls, NothingTravelsInClear) {
  // The tap works: without TLS it sees the token and the video.
  const std::string plain = Overheard(std::nullopt, std::nullopt);
  EXPECT_NE(plain.find("lab-token-0f3c9a"), std::string::npos);
  EXPECT_NE(plain.find("VIDEO-ROW-MARKER"), std::string::npos);
  // With TLS it sees 200 KB each way, and neither.
  const std::string tls = Overheard(TheLab().As("video"), TheLab().As("control"));
  EXPECT_GT(tls.size(), 400000u);
  EXPECT_EQ(tls.find("lab-token-0f3c9a"), std::string::npos);
  EXPECT_EQ(tls.find("VIDEO-ROW-MARKER"), std::string::npos);
  EXPECT_EQ(tls.find("VVVVVVVVVVVVVVVV"), std::string::npos);
}

}  // namespace
}  // namespace igms::net
