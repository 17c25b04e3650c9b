// One connection's session on the server (session.h): greeting and authentication, reading
// and dispatching frames, the write queue, and closing.
#include "common/net/session.h"

#include "common/net/server_impl.h"

namespace igms::net {

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
