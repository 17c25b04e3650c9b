#include "common/net/server.h"

#include <openssl/crypto.h>
#include <openssl/sha.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/write.hpp>
#include <ctime>
#include <future>
#include <stdexcept>

#include "common/base/clock.h"
#include "common/config/process_options.h"
#include "common/net/framing.h"
#include "common/net/session.h"
#include "common/version/version.h"

namespace igms::net {

namespace asio = boost::asio;
using asio::ip::tcp;

struct Server::Impl : std::enable_shared_from_this<Server::Impl> {
  Impl(asio::io_context& io, const ServerOptions& o)
      : io(io), options(o), strand(asio::make_strand(io)), acceptor(strand), limiter(o.failures) {}

  asio::io_context& io;
  ServerOptions options;
  asio::strand<asio::io_context::executor_type> strand;  // the acceptor's
  tcp::acceptor acceptor;
  std::map<std::string, MethodFn> methods;
  std::map<std::string, StreamFn> streams;
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();

  std::mutex mutex;  // guards sessions and stopped
  std::set<std::shared_ptr<Session>> sessions;
  bool stopped = false;
  std::atomic<bool> acceptor_closed{false};

  // TLS: the context new sessions take (replaced by ReloadTls), the table and the limiter.
  TlsOptions tls_options;
  std::shared_ptr<const TlsContext> tls;  // guarded by mutex; null: plain TCP
  Authorisation authorisation = Authorisation::Default();
  FailureLimiter limiter;
  std::unique_ptr<asio::signal_set> sighup;
  std::unique_ptr<asio::steady_timer> expiry_timer;

  void WarnIfExpiring(const TlsContext& context) {
    const std::string warning = context.ExpiryWarning(std::chrono::hours(24 * 7));
    if (!warning.empty()) spdlog::warn("{}: {}", options.name, warning);
  }

  bool Reload() {
    try {
      auto context = std::make_shared<const TlsContext>(tls_options, TlsContext::Role::kServer);
      WarnIfExpiring(*context);
      std::lock_guard lock(mutex);
      tls = std::move(context);
    } catch (const std::exception& e) {
      spdlog::error("{}: keeping the certificate in use: {}", options.name, e.what());
      return false;
    }
    spdlog::info("{}: certificate files read again; new connections use them", options.name);
    return true;
  }

  void WaitForSighup() {
    sighup->async_wait([self = shared_from_this()](const boost::system::error_code& ec, int) {
      if (ec) return;
      spdlog::info("{}: SIGHUP: reading the certificate files again", self->options.name);
      self->Reload();
      self->WaitForSighup();
    });
  }

  // A server runs for weeks: the week's notice of expiry is checked twice a day too.
  void CheckExpiryLater() {
    expiry_timer->expires_after(std::chrono::hours(12));
    expiry_timer->async_wait([self = shared_from_this()](const boost::system::error_code& ec) {
      if (ec) return;
      if (auto context = self->Tls()) self->WarnIfExpiring(*context);
      self->CheckExpiryLater();
    });
  }

  std::shared_ptr<const TlsContext> Tls() {
    std::lock_guard lock(mutex);
    return tls;
  }
  // A failed handshake or token from `address`; logged once per burst.
  void Failed(const std::string& address, const std::string& peer, const std::string& why) {
    if (limiter.Fail(address)) {
      spdlog::warn("{}: refused {}: {}", options.name, peer, why);
    } else {
      spdlog::debug("{}: refused {}: {}", options.name, peer, why);
    }
  }

  void Accept() {
    acceptor.async_accept(
        asio::make_strand(io),
        [self = shared_from_this()](boost::system::error_code ec, tcp::socket socket) {
          if (ec == asio::error::operation_aborted) return;
          if (ec) {
            // Out of file descriptors and the like: log, keep serving the others.
            spdlog::warn("{}: accept failed: {}", self->options.name, ec.message());
          } else if (boost::system::error_code e; true) {
            const auto remote = socket.remote_endpoint(e);
            bool announce = false;
            int failures = 0;
            if (!e && self->limiter.Blocked(remote.address().to_string(), &announce, &failures)) {
              // Too many failed handshakes or tokens from there: not even a handshake.
              if (announce) {
                spdlog::warn("{}: {} failed {} times in a row: refusing its connections for {} s",
                             self->options.name, remote.address().to_string(), failures,
                             self->options.failures.block.count() / 1000.0);
              }
              socket.close(e);
              self->Accept();
              return;
            }
            auto session = std::make_shared<Session>(std::move(socket), self);
            {
              std::lock_guard lock(self->mutex);
              if (self->stopped) return;
              self->sessions.insert(session);
            }
            session->Start();
          }
          self->Accept();
        });
  }

  void Forget(const std::shared_ptr<Session>& s) {
    std::lock_guard lock(mutex);
    sessions.erase(s);
  }
};

Server::Server(asio::io_context& io, ServerOptions options)
    : options_(std::move(options)), impl_(std::make_shared<Impl>(io, options_)) {
  AddMethod("igms.Server.Ping",
            [this](std::string_view, std::weak_ptr<Session> s, std::uint64_t id) {
              igms::PingResponse r;
              r.set_server_name(options_.name);
              r.set_program(version::ProgramName());
              r.set_version(version::Full());
              r.set_protocol_version(igms::PROTOCOL_VERSION_CURRENT);
              r.set_server_unix_ns(UnixNs());
              r.set_uptime_ms(std::chrono::duration_cast<std::chrono::milliseconds>(
                                  std::chrono::steady_clock::now() - impl_->started)
                                  .count());
              Reply<igms::PingResponse>(s, id, "igms.Server.Ping")(Status::Ok(), r);
            });
}

Server::~Server() { Stop(); }

void Server::AddMethod(const std::string& method, MethodFn fn) {
  impl_->methods[method] = std::move(fn);
}

void Server::AddStream(const std::string& method, StreamFn fn) {
  impl_->streams[method] = std::move(fn);
}

void Server::Start() {
  boost::system::error_code ec;
  const auto address = asio::ip::make_address(options_.bind_address, ec);
  if (ec) {
    throw std::runtime_error(options_.name + ": bad bind address '" + options_.bind_address +
                             "': " + ec.message());
  }
  const tcp::endpoint endpoint(address, options_.port);
  auto& acceptor = impl_->acceptor;
  acceptor.open(endpoint.protocol(), ec);
  if (!ec) acceptor.set_option(tcp::acceptor::reuse_address(true), ec);
  if (!ec) acceptor.bind(endpoint, ec);
  if (!ec) acceptor.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) {
    throw std::runtime_error(options_.name + ": cannot listen on " + options_.bind_address + ":" +
                             std::to_string(options_.port) + ": " + ec.message());
  }
  port_ = acceptor.local_endpoint().port();
  impl_->tls_options = options_.tls ? *options_.tls : TlsOptions::ForProcess();
  if (options_.authorisation) {
    impl_->authorisation = *options_.authorisation;
  } else {
    for (const auto& [pattern, names] : config::ProcessSecurity().permissions)
      impl_->authorisation.Set(pattern, names);
  }
  if (impl_->tls_options.enabled) {
    // A server whose certificate cannot be read does not start (rather than serve in clear).
    auto context =
        std::make_shared<const TlsContext>(impl_->tls_options, TlsContext::Role::kServer);
    impl_->WarnIfExpiring(*context);
    {
      std::lock_guard lock(impl_->mutex);
      impl_->tls = std::move(context);
    }
    if (options_.reload_on_sighup) {
      impl_->sighup = std::make_unique<asio::signal_set>(impl_->io, SIGHUP);
      impl_->WaitForSighup();
    }
    impl_->expiry_timer = std::make_unique<asio::steady_timer>(impl_->strand);
    impl_->CheckExpiryLater();
  }
  spdlog::info("{}: listening on {}:{}{}", options_.name, options_.bind_address, port_,
               impl_->tls_options.enabled ? " (TLS 1.3, mutual certificates)" : "");
  impl_->Accept();
}

bool Server::tls() const { return impl_->Tls() != nullptr; }

bool Server::ReloadTls() { return impl_->tls_options.enabled && impl_->Reload(); }

void Server::Stop() {
  std::set<std::shared_ptr<Session>> sessions;
  {
    std::lock_guard lock(impl_->mutex);
    if (impl_->stopped) return;
    impl_->stopped = true;
    sessions.swap(impl_->sessions);
  }
  if (impl_->sighup || impl_->expiry_timer) {
    // On the loop's thread: neither a signal set nor a timer is thread-safe.
    asio::post(impl_->strand, [impl = impl_] {
      boost::system::error_code ignored;
      if (impl->sighup) impl->sighup->cancel(ignored);
      if (impl->expiry_timer) impl->expiry_timer->cancel();
    });
  }
  // The port must be free when Stop returns to a caller outside the io_context (a test
  // restarting a server binds it again at once), so the close runs on the acceptor's
  // strand and Stop waits for it. Inside the strand, or with the io_context stopped, it
  // closes here; from another handler (a signal) it only posts, never blocking the loop.
  auto closed = std::make_shared<std::promise<void>>();
  auto done = closed->get_future();
  auto close_once = [impl = impl_, closed] {
    if (impl->acceptor_closed.exchange(true)) return;
    boost::system::error_code ignored;
    impl->acceptor.close(ignored);
    closed->set_value();
  };
  const auto& strand = impl_->strand;
  if (strand.running_in_this_thread() || impl_->io.stopped()) {
    close_once();
  } else {
    asio::post(strand, close_once);
    const bool outside_loop = !impl_->io.get_executor().running_in_this_thread();
    if (outside_loop && done.wait_for(std::chrono::seconds(1)) != std::future_status::ready)
      close_once();
  }
  for (auto& s : sessions) s->Close("server shutting down");
}

std::size_t Server::session_count() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->sessions.size();
}

// ---------------------------------------------------------------------------------------
// Session

namespace {

// Constant time whatever the two hold: digests of equal length compared with CRYPTO_memcmp,
// so neither the position of the first wrong byte nor the token's length shows in the time.
bool TokensEqual(const std::string& presented, const std::string& expected) {
  unsigned char a[SHA256_DIGEST_LENGTH], b[SHA256_DIGEST_LENGTH];
  SHA256(reinterpret_cast<const unsigned char*>(presented.data()), presented.size(), a);
  SHA256(reinterpret_cast<const unsigned char*>(expected.data()), expected.size(), b);
  return CRYPTO_memcmp(a, b, sizeof a) == 0;
}

}  // namespace

namespace detail {

bool Send(const std::weak_ptr<Session>& session, std::string frame, std::uint64_t key) {
  auto s = session.lock();
  return s && s->Send(std::move(frame), key);
}

std::string Frame(const igms::Envelope& envelope, const google::protobuf::MessageLite& payload) {
  std::string out;
  AppendFrame(envelope, payload, &out);
  return out;
}

std::string Frame(const igms::Envelope& envelope) { return EncodeFrame(envelope); }

bool SubscriptionOpen(const std::weak_ptr<Session>& session, std::uint64_t id) {
  auto s = session.lock();
  return s && s->SubscriptionOpen(id);
}

igms::Envelope MakeEnvelope(igms::Envelope::Kind kind, std::uint64_t correlation_id,
                            const std::string& method) {
  return net::MakeEnvelope(kind, correlation_id, method);
}

Caller CallerOf(const std::weak_ptr<Session>& session) {
  auto s = session.lock();
  if (!s) return Caller{session, "", "", ""};
  return s->Describe();
}

}  // namespace detail

std::string Caller::Describe() const {
  std::string who = name.empty() ? "an unnamed client" : name;
  if (!certificate.empty() && certificate != name) who += " (certificate " + certificate + ")";
  return who + " at " + (address.empty() ? "an unknown address" : address);
}

bool Caller::connected() const {
  auto s = session.lock();
  return s && !s->closed();
}

bool Caller::SameConnection(const Caller& other) const {
  return !session.owner_before(other.session) && !other.session.owner_before(session);
}

Caller Session::Describe() { return Caller{weak_from_this(), client_name_, endpoint_, peer_name_}; }

bool Session::closed() {
  std::lock_guard lock(mutex_);
  return closed_;
}

Session::Session(tcp::socket socket, std::shared_ptr<Server::Impl> server)
    : socket_(std::move(socket)),
      server_(std::move(server)),
      idle_timer_(socket_.get_executor()),
      authenticated_(server_->options.token.empty()) {
  boost::system::error_code ec;
  const auto remote = socket_.remote_endpoint(ec);
  address_ = ec ? "unknown" : remote.address().to_string();
  peer_ = ec ? "unknown peer" : address_ + ":" + std::to_string(remote.port());
  endpoint_ = peer_;
  socket_.set_option(tcp::no_delay(true), ec);
  if (auto context = server_->Tls()) tls_ = std::make_shared<TlsStream>(socket_, context, "");
}

void Session::Start() {
  asio::dispatch(socket_.get_executor(), [self = shared_from_this()] {
    self->ArmIdleTimer();  // also bounds a handshake that never ends
    if (!self->tls_) {
      self->ReadMore();
      return;
    }
    self->tls_->AsyncHandshake([self](const std::string& error) { self->OnHandshake(error); });
  });
}

void Session::OnHandshake(const std::string& error) {
  if (!error.empty()) {
    server_->Failed(address_, peer_, error);
    if (tls_->engine().peer_spoke_plaintext()) {
      // A plain IGMS client: tell it in its own words, then close.
      auto frame = std::make_shared<std::string>(EncodeFrame([&] {
        igms::Envelope e = detail::MakeEnvelope(igms::Envelope::ERROR, 0, "");
        e.mutable_error()->set_code(igms::UNAUTHENTICATED);
        e.mutable_error()->set_message(server_->options.name +
                                       " requires TLS (lab.tls: on) and this client spoke plain "
                                       "TCP: give it the lab's lab.tls and certificates");
        return e;
      }()));
      asio::async_write(socket_, asio::buffer(*frame),
                        [self = shared_from_this(), frame](boost::system::error_code, std::size_t) {
                          self->Close("rejected");
                        });
      return;
    }
    Close("rejected");
    return;
  }
  peer_name_ = tls_->PeerName();
  peer_ += " (" + peer_name_ + ")";
  spdlog::debug("{}: {} authenticated by its certificate", server_->options.name, peer_);
  ReadMore();
}

void Session::ArmIdleTimer() {
  // One timer per session that checks the time of the last frame, rather than re-arming a
  // timer on every read (two system calls a frame on a busy session).
  const auto timeout = server_->options.idle_timeout;
  const auto since = std::chrono::steady_clock::now() - last_activity_;
  idle_timer_.expires_after(since >= timeout ? timeout : timeout - since);
  idle_timer_.async_wait([weak = weak_from_this()](boost::system::error_code ec) {
    if (ec) return;
    auto self = weak.lock();
    if (!self) return;
    if (std::chrono::steady_clock::now() - self->last_activity_ >=
        self->server_->options.idle_timeout) {
      self->Close("idle for longer than the idle timeout");
    } else {
      self->ArmIdleTimer();
    }
  });
}

void Session::ReadMore() {
  // Idle sessions keep a small buffer; a large frame gets room for all of it at once.
  in_.shrink_if_idle(1u << 20);
  const std::size_t need = std::max<std::size_t>(BytesStillNeeded(in_.pending()), 4096);
  char* at = in_.prepare(need);
  if (tls_) {
    tls_->AsyncReadSome(at, in_.room(),
                        [self = shared_from_this()](const std::string& error, std::size_t n) {
                          self->OnRead(error == "eof" ? "peer closed the connection" : error, n);
                        });
    return;
  }
  socket_.async_read_some(asio::buffer(at, in_.room()),
                          [self = shared_from_this()](boost::system::error_code ec, std::size_t n) {
                            self->OnRead(!ec                      ? ""
                                         : ec == asio::error::eof ? "peer closed the connection"
                                                                  : ec.message(),
                                         n);
                          });
}

bool Session::LooksLikeTls() const {
  // A TLS ClientHello record: type 22, version 3.x. No IGMS frame starts so (its second
  // byte would be a protobuf tag of field 0).
  const auto p = in_.pending();
  return p.size() >= 2 && static_cast<unsigned char>(p[0]) == 0x16 && p[1] == 0x03;
}

void Session::OnRead(const std::string& error, std::size_t n) {
  if (!error.empty()) {
    Close(error);
    return;
  }
  in_.commit(n);
  last_activity_ = std::chrono::steady_clock::now();
  if (first_read_ && !tls_) {
    first_read_ = false;
    if (LooksLikeTls()) {
      server_->Failed(address_, peer_, "a TLS client, and this server speaks plain TCP");
      SendError(0, "", igms::UNAUTHENTICATED,
                server_->options.name +
                    " speaks plain TCP (lab.tls: off) and this client "
                    "tried TLS",
                true);
      return;
    }
  }
  for (;;) {
    DecodeResult r = DecodeFrame(in_.pending(), server_->options.max_frame_bytes);
    if (r.status == DecodeStatus::kNeedMore) break;
    if (r.status == DecodeStatus::kError) {
      Close("bad frame: " + r.error);
      return;
    }
    OnFrame(r.frame);
    in_.consume(r.consumed);
    {
      std::lock_guard lock(mutex_);
      if (closed_) return;
    }
  }
  ReadMore();
}

void Session::OnFrame(std::string_view frame) {
  igms::Envelope envelope;
  std::string_view payload;
  std::string error;
  if (!ParseEnvelopeView(frame, &envelope, &payload, &error)) {
    Close("bad frame: " + error);
    return;
  }
  Dispatch(envelope, payload);
}

void Session::Dispatch(igms::Envelope& e, std::string_view payload) {
  const auto id = e.header().correlation_id();
  const auto& options = server_->options;
  if (e.kind() == igms::Envelope::HELLO) {
    const auto version = e.header().protocol_version();
    if (version != 0 && version != igms::PROTOCOL_VERSION_CURRENT) {
      SendError(id, "", igms::VERSION_MISMATCH,
                "protocol version " + std::to_string(version) +
                    " is not supported (this server "
                    "speaks " +
                    std::to_string(igms::PROTOCOL_VERSION_CURRENT) + ")",
                true);
      return;
    }
    if (!options.token.empty() && !TokensEqual(e.token(), options.token)) {
      server_->Failed(address_, peer_, "a wrong token");
      SendError(id, "", igms::UNAUTHENTICATED, "the lab token is missing or wrong", true);
      return;
    }
    authenticated_ = true;
    client_name_ = e.header().sender();
    return;
  }
  if (!authenticated_) {
    spdlog::warn("{}: {} sent {} before authenticating", options.name, peer_,
                 igms::Envelope::Kind_Name(e.kind()));
    SendError(id, e.method(), igms::UNAUTHENTICATED,
              "this lab requires a token: send HELLO with it first", true);
    return;
  }
  switch (e.kind()) {
    case igms::Envelope::HEARTBEAT:
      return;
    case igms::Envelope::REQUEST: {
      if (!Permitted(id, e.method())) return;
      if (client_name_.empty()) client_name_ = e.header().sender();
      auto it = server_->methods.find(e.method());
      if (it == server_->methods.end()) {
        SendError(id, e.method(), igms::UNKNOWN_METHOD,
                  "no method '" + e.method() + "' on " + options.name, false);
        return;
      }
      try {
        it->second(payload, weak_from_this(), id);
      } catch (const std::exception& ex) {
        spdlog::error("{}: {} threw: {}", options.name, e.method(), ex.what());
        SendError(id, e.method(), igms::INTERNAL, ex.what(), false);
      }
      return;
    }
    case igms::Envelope::SUBSCRIBE: {
      if (!Permitted(id, e.method())) return;
      auto it = server_->streams.find(e.method());
      if (it == server_->streams.end()) {
        SendError(id, e.method(), igms::UNKNOWN_METHOD,
                  "no stream '" + e.method() + "' on " + options.name, false);
        return;
      }
      {
        std::lock_guard lock(mutex_);
        subscriptions_.insert(id);
      }
      Status status;
      try {
        status = it->second(payload, weak_from_this(), id);
      } catch (const std::exception& ex) {
        status = Status::Error(igms::INTERNAL, ex.what());
      }
      if (!status.ok()) {
        {
          std::lock_guard lock(mutex_);
          subscriptions_.erase(id);
        }
        SendError(id, e.method(), status.code, status.message, false);
      }
      return;
    }
    case igms::Envelope::UNSUBSCRIBE: {
      std::lock_guard lock(mutex_);
      subscriptions_.erase(id);
      return;
    }
    default:
      SendError(id, e.method(), igms::BAD_REQUEST,
                "a client may not send " + igms::Envelope::Kind_Name(e.kind()), false);
  }
}

bool Session::Permitted(std::uint64_t id, const std::string& method) {
  // Judged by the certificate's name; a plain connection has none, and is not judged.
  if (!tls_ || method == "igms.Server.Ping") return true;
  const auto& table = server_->authorisation;
  if (table.Allowed(method, peer_name_)) return true;
  spdlog::warn("{}: refused {} to {}: only {} may call it", server_->options.name, method, peer_,
               table.WhoMay(method));
  SendError(id, method, igms::PERMISSION_DENIED,
            "the certificate '" + peer_name_ + "' may not call " + method + " on " +
                server_->options.name + " (only " + table.WhoMay(method) + ")",
            false);
  return false;
}

void Session::SendError(std::uint64_t id, const std::string& method, igms::ErrorCode code,
                        const std::string& message, bool close_after) {
  igms::Envelope e = detail::MakeEnvelope(igms::Envelope::ERROR, id, method);
  e.mutable_error()->set_code(code);
  e.mutable_error()->set_message(message);
  if (close_after) {
    close_after_write_ = true;
    // Stop reading: nothing more from this peer is served.
    boost::system::error_code ignored;
    socket_.shutdown(tcp::socket::shutdown_receive, ignored);
  }
  Send(EncodeFrame(e), 0);
}

bool Session::Send(std::string frame, std::uint64_t latest_only_key) {
  Outgoing out;
  out.bytes = std::move(frame);
  out.stream_id = latest_only_key;
  bool start = false;
  {
    std::lock_guard lock(mutex_);
    if (closed_) return false;
    bool replaced = false;
    if (out.stream_id != 0) {
      for (auto& q : queue_) {
        if (q.stream_id == out.stream_id) {
          queued_bytes_ = queued_bytes_ - q.bytes.size() + out.bytes.size();
          q.bytes.swap(out.bytes);
          replaced = true;
          break;
        }
      }
    }
    if (!replaced) {
      queued_bytes_ += out.bytes.size();
      queue_.push_back(std::move(out));
    }
    if (queued_bytes_ > server_->options.max_write_queue_bytes) {
      // The peer stopped reading; it must not hold memory or the others hostage.
      asio::post(socket_.get_executor(), [self = shared_from_this()] {
        self->Close("write queue over its limit: the client is not reading");
      });
      return false;
    }
    if (!writing_) {
      writing_ = true;
      start = true;
    }
  }
  // dispatch: a handler answering on the session's own strand writes without a hop.
  if (start)
    asio::dispatch(socket_.get_executor(), [self = shared_from_this()] { self->WriteNext(); });
  return true;
}

bool Session::NothingToWriteLocked() {
  if (closed_) return true;
  if (!queue_.empty()) return false;
  writing_ = false;
  if (close_after_write_) {
    // The error that ends this session has been written.
    asio::post(socket_.get_executor(), [self = shared_from_this()] { self->Close("rejected"); });
  }
  return true;
}

void Session::WriteNext() {
  if (tls_) {
    WriteNextTls();
    return;
  }
  auto current = std::make_shared<std::string>();
  {
    std::lock_guard lock(mutex_);
    if (NothingToWriteLocked()) return;
    current->swap(queue_.front().bytes);
    queued_bytes_ -= current->size();
    queue_.pop_front();
  }
  asio::async_write(
      socket_, asio::buffer(*current),
      [self = shared_from_this(), current](boost::system::error_code ec, std::size_t) {
        if (ec) {
          self->Close("write failed: " + ec.message());
          return;
        }
        self->WriteNext();
      });
}

void Session::WriteNextTls() {
  // Everything queued is encrypted now and goes to the socket in one write.
  std::deque<Outgoing> batch;
  {
    std::lock_guard lock(mutex_);
    if (NothingToWriteLocked()) return;
    batch.swap(queue_);
    queued_bytes_ = 0;
  }
  for (const auto& out : batch) {
    if (!tls_->Encrypt(out.bytes.data(), out.bytes.size())) {
      Close("TLS: " + tls_->engine().error());
      return;
    }
  }
  tls_->Flush([self = shared_from_this()](const std::string& error) {
    if (!error.empty()) {
      self->Close(error);
      return;
    }
    self->WriteNext();
  });
}

bool Session::SubscriptionOpen(std::uint64_t id) {
  std::lock_guard lock(mutex_);
  return !closed_ && subscriptions_.count(id) > 0;
}

void Session::Close(const std::string& reason) {
  asio::dispatch(socket_.get_executor(), [self = shared_from_this(), reason] {
    {
      std::lock_guard lock(self->mutex_);
      if (self->closed_) return;
      self->closed_ = true;
      self->subscriptions_.clear();
      self->queue_.clear();
      self->queued_bytes_ = 0;
    }
    const bool normal = reason == "peer closed the connection" || reason == "rejected" ||
                        reason == "server shutting down";
    if (normal) {
      spdlog::debug("{}: {} closed: {}", self->server_->options.name, self->peer_, reason);
    } else {
      spdlog::warn("{}: closing {}: {}", self->server_->options.name, self->peer_, reason);
    }
    boost::system::error_code ignored;
    self->idle_timer_.cancel();
    if (self->tls_) self->tls_->Shutdown();
    self->socket_.shutdown(tcp::socket::shutdown_both, ignored);
    self->socket_.close(ignored);
    self->server_->Forget(self);
  });
}

}  // namespace igms::net
