// The server base every IGMS process builds on (Boost.Asio, one session object per client).
//
// A server registers methods by their full protobuf name ("igms.video.VideoService.Grab"):
//  - Handle: a quick handler run on the network thread, returning a Status.
//  - HandleAsync: the handler gets a Reply it may call later from any thread (exactly once);
//    slow work (locating an object, waiting for edges) goes to a worker this way.
//  - HandleStream: a subscription; the handler keeps a Publisher and sends from any thread
//    until Publisher::closed(). With latest_only, a message not yet written is replaced by a
//    newer one, so a slow subscriber gets the newest frame and never a growing queue.
// Every server answers "igms.Server.Ping".
//
// Each session has its own write queue with one write in flight; a session whose queue
// passes max_write_queue_bytes (a client that stopped reading) is closed, so it cannot stall
// or exhaust the others. A frame over max_frame_bytes, or one that does not parse, closes
// that session with a logged reason. When a token is set, a client must present it in its
// HELLO before anything else; otherwise it gets UNAUTHENTICATED and is disconnected.
// Sessions idle (nothing received) longer than idle_timeout are closed; clients send
// heartbeats. Stop() closes the acceptor and every session.
//
// With TLS (ServerOptions::tls, by default the lab's lab.tls), every session starts with a
// TLS 1.3 handshake that needs a client certificate of the lab's authority; each request is
// then checked against the authorisation table by the certificate's name, and a refused one
// answers PERMISSION_DENIED. Failed handshakes and tokens are rate-limited per address.
// ReloadTls() (and SIGHUP) re-reads the certificate files for new sessions; sessions up keep
// theirs. The token is compared in constant time. docs/security.md.
#pragma once

#include <google/protobuf/message_lite.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>

#include "common/net/authorisation.h"
#include "common/net/failure_limiter.h"
#include "common/net/status.h"
#include "common/net/tls.h"

namespace igms::net {

struct ServerOptions {
  std::string name = "server";             // for logs and Ping
  std::string bind_address = "127.0.0.1";  // loopback unless the lab says otherwise
  std::uint16_t port = 0;                  // 0: any free port (tests)
  std::size_t max_frame_bytes = 4u << 20;
  std::size_t max_write_queue_bytes = 64u << 20;
  std::chrono::milliseconds idle_timeout{30000};
  std::string token;  // empty: no authentication
  // nullopt: the process's lab settings (TlsOptions::ForProcess: plain unless lab.tls: on).
  std::optional<TlsOptions> tls;
  // nullopt: the built-in table with the lab's lab.permissions over it.
  std::optional<Authorisation> authorisation;
  FailureLimiter::Options failures;
  bool reload_on_sighup = true;  // with TLS
};

class Session;

// Who sent a request, for the few methods that must know (the platform's one controlling
// client): its connection, the name it gave in its HELLO, its address and, with TLS, its
// certificate's name. Holding one does not keep the connection open.
struct Caller {
  std::weak_ptr<Session> session;
  std::string name;         // the HELLO's sender ("control", "igmsctl"); may be empty
  std::string address;      // "127.0.0.1:40312"
  std::string certificate;  // the certificate's name, with TLS; else empty
  // For a person: "control at 127.0.0.1:40312", "igmsctl (certificate control) at ...".
  std::string Describe() const;
  // False once its connection has closed (or the server has stopped).
  bool connected() const;
  bool SameConnection(const Caller& other) const;
};

namespace detail {
// Queues a frame on a session from any thread; false if the session is gone. A non-zero
// latest_only_key replaces a queued, unwritten frame with the same key.
bool Send(const std::weak_ptr<Session>& session, std::string frame, std::uint64_t latest_only_key);
// Frames an envelope around a message (serialized once, straight into the frame).
std::string Frame(const igms::Envelope& envelope, const google::protobuf::MessageLite& payload);
std::string Frame(const igms::Envelope& envelope);
bool SubscriptionOpen(const std::weak_ptr<Session>& session, std::uint64_t id);
igms::Envelope MakeEnvelope(igms::Envelope::Kind kind, std::uint64_t correlation_id,
                            const std::string& method);
Caller CallerOf(const std::weak_ptr<Session>& session);
}  // namespace detail

// Answers one request, once, from any thread.
template <class Resp>
class Reply {
 public:
  Reply(std::weak_ptr<Session> s, std::uint64_t id, std::string method)
      : session_(std::move(s)), id_(id), method_(std::move(method)) {}
  void operator()(const Status& status, const Resp& response = Resp()) const {
    igms::Envelope e = detail::MakeEnvelope(
        status.ok() ? igms::Envelope::RESPONSE : igms::Envelope::ERROR, id_, method_);
    if (status.ok()) {
      detail::Send(session_, detail::Frame(e, response), 0);
    } else {
      e.mutable_error()->set_code(status.code);
      e.mutable_error()->set_message(status.message);
      detail::Send(session_, detail::Frame(e), 0);
    }
  }

 private:
  std::weak_ptr<Session> session_;
  std::uint64_t id_;
  std::string method_;
};

// One subscriber's end of a stream. Thread-safe.
template <class Msg>
class Publisher {
 public:
  Publisher(std::weak_ptr<Session> s, std::uint64_t id, std::string method, bool latest_only)
      : session_(std::move(s)), id_(id), method_(std::move(method)), latest_only_(latest_only) {}
  // False once the subscriber is gone or unsubscribed: drop the publisher then.
  bool Send(const Msg& message) const {
    if (closed()) return false;
    const igms::Envelope e = detail::MakeEnvelope(igms::Envelope::STREAM, id_, method_);
    return detail::Send(session_, detail::Frame(e, message), latest_only_ ? id_ : 0);
  }
  bool closed() const { return !detail::SubscriptionOpen(session_, id_); }

 private:
  std::weak_ptr<Session> session_;
  std::uint64_t id_;
  std::string method_;
  bool latest_only_;
};

class Server {
 public:
  Server(boost::asio::io_context& io, ServerOptions options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  template <class Req, class Resp>
  void Handle(const std::string& method, std::function<Status(const Req&, Resp&)> fn) {
    HandleAsync<Req, Resp>(method, [fn](const Req& req, Reply<Resp> reply) {
      Resp resp;
      Status status = fn(req, resp);
      reply(status, resp);
    });
  }

  template <class Req, class Resp>
  void HandleAsync(const std::string& method, std::function<void(const Req&, Reply<Resp>)> fn) {
    HandleAsyncFrom<Req, Resp>(method, [fn](const Caller&, const Req& req, Reply<Resp> reply) {
      fn(req, std::move(reply));
    });
  }

  // HandleAsync for a handler that must know who is calling.
  template <class Req, class Resp>
  void HandleAsyncFrom(const std::string& method,
                       std::function<void(const Caller&, const Req&, Reply<Resp>)> fn) {
    AddMethod(method,
              [fn, method](std::string_view payload, std::weak_ptr<Session> s, std::uint64_t id) {
                Req req;
                if (!req.ParseFromArray(payload.data(), static_cast<int>(payload.size()))) {
                  Reply<Resp>(s, id, method)(
                      Status::Error(igms::BAD_REQUEST, "payload is not a " + req.GetTypeName()));
                  return;
                }
                fn(detail::CallerOf(s), req, Reply<Resp>(s, id, method));
              });
  }

  template <class Req, class Msg>
  void HandleStream(const std::string& method,
                    std::function<Status(const Req&, std::shared_ptr<Publisher<Msg>>)> fn,
                    bool latest_only = false) {
    AddStream(method, [fn, method, latest_only](std::string_view payload, std::weak_ptr<Session> s,
                                                std::uint64_t id) {
      Req req;
      if (!req.ParseFromArray(payload.data(), static_cast<int>(payload.size()))) {
        return Status::Error(igms::BAD_REQUEST, "payload is not a " + req.GetTypeName());
      }
      return fn(req, std::make_shared<Publisher<Msg>>(s, id, method, latest_only));
    });
  }

  // Binds and starts accepting. Throws std::runtime_error naming the address if it cannot.
  void Start();
  // Closes the acceptor and every session; safe from any thread, and more than once.
  void Stop();
  std::uint16_t port() const { return port_; }
  std::size_t session_count() const;
  bool tls() const;
  // Re-reads the certificate files; new sessions use them, sessions up keep theirs. False
  // (the old ones stay) when they cannot be read; the log says why.
  bool ReloadTls();
  const ServerOptions& options() const { return options_; }

  // Used by sessions.
  struct Impl;

 private:
  using MethodFn = std::function<void(std::string_view, std::weak_ptr<Session>, std::uint64_t)>;
  using StreamFn = std::function<Status(std::string_view, std::weak_ptr<Session>, std::uint64_t)>;
  void AddMethod(const std::string& method, MethodFn fn);
  void AddStream(const std::string& method, StreamFn fn);

  ServerOptions options_;
  std::shared_ptr<Impl> impl_;
  std::uint16_t port_ = 0;
};

}  // namespace igms::net
