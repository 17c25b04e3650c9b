#include "common/net/client.h"

#include <spdlog/spdlog.h>
#include <sys/socket.h>

#include <algorithm>
#include <atomic>
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/write.hpp>
#include <cerrno>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>

#include "common/base/clock.h"
#include "common/net/framing.h"
#include "common/net/read_buffer.h"

namespace igms::net {

namespace asio = boost::asio;
using asio::ip::tcp;

struct Client::Impl : std::enable_shared_from_this<Client::Impl> {
  struct Pending {
    std::string method;
    std::string frame;  // kept until sent
    RawDone done;
    std::chrono::steady_clock::time_point deadline;
    std::chrono::milliseconds timeout;
    bool sent = false;
  };
  struct Subscription {
    std::string frame;  // the SUBSCRIBE, sent again after every reconnect
    RawStream on_message;
    std::function<void(const Status&)> on_error;
  };

  Impl(asio::io_context& io, ClientOptions o)
      : options(std::move(o)),
        strand(asio::make_strand(io)),
        socket(strand),
        resolver(strand),
        connect_timer(strand),
        retry_timer(strand),
        heartbeat_timer(strand),
        deadline_timer(strand) {}

  ClientOptions options;
  asio::strand<asio::io_context::executor_type> strand;
  tcp::socket socket;
  // With TLS: the context (made at Start) and the connection's stream (one per connection).
  std::shared_ptr<const TlsContext> tls_context;
  std::string tls_error;  // why the context could not be made
  std::shared_ptr<TlsStream> tls;
  tcp::resolver resolver;
  asio::steady_timer connect_timer, retry_timer, heartbeat_timer;
  // Fires at the earliest deadline of the calls in flight; one timer for all of them, so a
  // call costs no timer system calls of its own.
  asio::steady_timer deadline_timer;
  std::atomic<std::uint64_t> next_id{1};

  // A call is sent from the caller's thread when the connection is up and nothing else is
  // being written: a round trip then costs no hand-over to the io thread on the way out.
  // write_mutex guards the write queue and the right to use the socket's descriptor from
  // another thread; it is taken before calls_mutex when both are needed.
  std::mutex write_mutex;
  std::deque<std::string> out;
  bool writing = false;  // a write is in flight (async_write, or a queued remainder)
  bool live = false;     // connected, greeted: callers may write directly
  std::uint64_t live_generation = 0;
  std::atomic<bool> sent_since_heartbeat{false};

  // Calls in flight, registered from any thread, answered on the strand.
  std::mutex calls_mutex;
  std::map<std::uint64_t, Pending> pending;
  std::chrono::steady_clock::time_point deadline_armed =
      std::chrono::steady_clock::time_point::max();

  // Touched only on the strand.
  std::map<std::uint64_t, Subscription> subscriptions;
  ReadBuffer in;
  std::chrono::milliseconds backoff{100};
  std::uint64_t generation = 0;  // bumps on every (re)connection attempt
  std::string last_server_error;
  std::string gave_up;  // why, once a client that does not reconnect has lost its connection
  std::function<void(ConnectionState, const std::string&)> on_state;

  // Read from any thread.
  std::mutex state_mutex;
  std::condition_variable state_cv;
  ConnectionState state = ConnectionState::kDisconnected;
  bool stopped = false;

  void SetState(ConnectionState s, const std::string& why) {
    {
      std::lock_guard lock(state_mutex);
      state = s;
    }
    state_cv.notify_all();
    if (on_state) on_state(s, why);
  }

  std::string Where() const { return options.host + ":" + std::to_string(options.port); }

  igms::Envelope Make(igms::Envelope::Kind kind, std::uint64_t id, const std::string& method) {
    igms::Envelope e = MakeEnvelope(kind, id, method);
    e.mutable_header()->set_sender(options.name);
    return e;
  }

  // On the strand.
  void Write(const igms::Envelope& e) { WriteFrame(EncodeFrame(e)); }
  void WriteFrame(std::string frame) {
    std::unique_lock lock(write_mutex);
    if (!QueueLocked(std::move(frame))) return;
    lock.unlock();
    WriteNext(generation);
  }
  // Queues a frame; true when the caller must start the writer (WriteNext).
  bool QueueLocked(std::string frame) {
    out.push_back(std::move(frame));
    sent_since_heartbeat = true;
    if (writing) return false;
    writing = true;
    return true;
  }

  // On the strand, with `writing` set: sends the queue one frame after another (with TLS,
  // all of it, encrypted, in one write).
  void WriteNext(std::uint64_t gen) {
    std::unique_lock lock(write_mutex);
    if (gen != generation) return;  // Drop has reset the queue
    if (tls) {
      if (out.empty()) {
        writing = false;
        return;
      }
      std::deque<std::string> batch;
      batch.swap(out);
      lock.unlock();
      for (const auto& frame : batch) {
        if (!tls->Encrypt(frame.data(), frame.size())) {
          Drop("TLS: " + tls->engine().error());
          return;
        }
      }
      tls->Flush([self = shared_from_this(), gen](const std::string& error) {
        if (gen != self->generation) return;
        if (!error.empty()) {
          self->Drop(error);
          return;
        }
        self->WriteNext(gen);
      });
      return;
    }
    if (out.empty()) {
      writing = false;
      return;
    }
    auto bytes = std::make_shared<std::string>(std::move(out.front()));
    out.pop_front();
    lock.unlock();
    asio::async_write(
        socket, asio::buffer(*bytes),
        [self = shared_from_this(), bytes, gen](boost::system::error_code ec, std::size_t) {
          if (gen != self->generation) return;
          if (ec) {
            self->Drop("write failed: " + ec.message());
            return;
          }
          self->WriteNext(gen);
        });
  }

  // On the caller's thread, with write_mutex held, live set and nothing in flight: writes
  // what the kernel takes now; the rest (if any) goes to the strand's writer.
  void SendDirectLocked(std::string frame) {
    sent_since_heartbeat = true;
    std::size_t done = 0;
    while (done < frame.size()) {
      const ssize_t n = ::send(socket.native_handle(), frame.data() + done, frame.size() - done,
                               MSG_DONTWAIT | MSG_NOSIGNAL);
      if (n > 0) {
        done += static_cast<std::size_t>(n);
      } else if (n < 0 && errno == EINTR) {
        continue;
      } else {
        break;  // full socket buffer, or an error the strand's writer will report
      }
    }
    if (done == frame.size()) return;
    out.push_back(frame.substr(done));
    writing = true;
    asio::post(strand,
               [self = shared_from_this(), gen = live_generation] { self->WriteNext(gen); });
  }

  void Connect() {
    if (IsStopped()) return;
    ++generation;
    const auto gen = generation;
    tls.reset();
    if (!tls_error.empty()) {
      Drop(tls_error);
      return;
    }
    SetState(ConnectionState::kConnecting, "connecting to " + Where());
    connect_timer.expires_after(options.connect_timeout);
    connect_timer.async_wait([self = shared_from_this(), gen](boost::system::error_code ec) {
      if (ec || gen != self->generation) return;
      boost::system::error_code ignored;
      self->resolver.cancel();
      self->socket.close(ignored);  // the pending connect completes with operation_aborted
    });
    resolver.async_resolve(
        options.host, std::to_string(options.port),
        [self = shared_from_this(), gen](boost::system::error_code ec,
                                         tcp::resolver::results_type results) {
          if (gen != self->generation) return;
          if (ec) {
            self->Drop("cannot resolve " + self->options.host + ": " + ec.message());
            return;
          }
          asio::async_connect(self->socket, results,
                              [self, gen](boost::system::error_code ec, const tcp::endpoint&) {
                                if (gen != self->generation) return;
                                self->connect_timer.cancel();
                                if (ec) {
                                  self->Drop(ec == asio::error::operation_aborted
                                                 ? "connect timed out"
                                                 : ec.message());
                                  return;
                                }
                                self->OnConnected();
                              });
        });
  }

  void OnConnected() {
    boost::system::error_code ignored;
    socket.set_option(tcp::no_delay(true), ignored);
    if (!tls_context) {
      OnSecured();
      return;
    }
    tls = std::make_shared<TlsStream>(socket, tls_context, options.host);
    tls->AsyncHandshake([self = shared_from_this(), gen = generation](const std::string& error) {
      if (gen != self->generation) return;
      if (!error.empty()) {
        self->Drop("TLS: " + error);
        return;
      }
      self->OnSecured();
    });
  }

  // Connected, and with TLS past the handshake.
  void OnSecured() {
    backoff = std::chrono::milliseconds(100);
    last_server_error.clear();
    in = ReadBuffer();
    {
      // The greeting, the calls that waited and the subscriptions go first, in that order;
      // only then may callers write directly.
      std::lock_guard lock(write_mutex);
      out.clear();
      writing = false;
      igms::Envelope hello = Make(igms::Envelope::HELLO, 0, "");
      hello.set_token(options.token);
      QueueLocked(EncodeFrame(hello));
      {
        std::lock_guard calls(calls_mutex);
        for (auto& [id, p] : pending) {
          if (!p.sent) {
            QueueLocked(std::move(p.frame));
            p.sent = true;
          }
        }
      }
      for (auto& [id, s] : subscriptions) QueueLocked(s.frame);
      live = true;
      live_generation = generation;
    }
    WriteNext(generation);
    SetState(ConnectionState::kConnected, "connected to " + Where());
    Read(generation);
    Heartbeat(generation);
  }

  void Heartbeat(std::uint64_t gen) {
    heartbeat_timer.expires_after(options.heartbeat_interval);
    heartbeat_timer.async_wait([self = shared_from_this(), gen](boost::system::error_code ec) {
      if (ec || gen != self->generation || self->IsStopped()) return;
      if (!self->sent_since_heartbeat.exchange(false)) {
        self->Write(self->Make(igms::Envelope::HEARTBEAT, 0, ""));
        self->sent_since_heartbeat = false;
      }
      self->Heartbeat(gen);
    });
  }

  void Read(std::uint64_t gen) {
    in.shrink_if_idle(1u << 20);
    const std::size_t need = std::max<std::size_t>(BytesStillNeeded(in.pending()), 4096);
    char* at = in.prepare(need);
    if (tls) {
      tls->AsyncReadSome(at, in.room(),
                         [self = shared_from_this(), gen](const std::string& error, std::size_t n) {
                           if (gen != self->generation) return;
                           self->OnRead(gen,
                                        error == "eof"  ? "server closed the connection"
                                        : error.empty() ? ""
                                                        : "TLS: " + error,
                                        n);
                         });
      return;
    }
    socket.async_read_some(
        asio::buffer(at, in.room()),
        [self = shared_from_this(), gen](boost::system::error_code ec, std::size_t n) {
          if (gen != self->generation) return;
          self->OnRead(gen,
                       !ec                      ? ""
                       : ec == asio::error::eof ? "server closed the connection"
                                                : ec.message(),
                       n);
        });
  }

  void OnRead(std::uint64_t gen, const std::string& error, std::size_t n) {
    auto* self = this;
    {
      {
        if (!error.empty()) {
          self->Drop(error);
          return;
        }
        self->in.commit(n);
        for (;;) {
          DecodeResult r = DecodeFrame(self->in.pending(), self->options.max_frame_bytes);
          if (r.status == DecodeStatus::kNeedMore) break;
          if (r.status == DecodeStatus::kError) {
            self->Drop("bad frame from server: " + r.error);
            return;
          }
          igms::Envelope e;
          std::string_view payload;
          std::string error;
          if (!ParseEnvelopeView(r.frame, &e, &payload, &error)) {
            self->Drop("bad frame from server: " + error);
            return;
          }
          self->OnEnvelope(e, payload);
          self->in.consume(r.consumed);
          if (gen != self->generation) return;
        }
        self->Read(gen);
      }
    }
  }

  void OnEnvelope(igms::Envelope& e, std::string_view payload) {
    const auto id = e.header().correlation_id();
    switch (e.kind()) {
      case igms::Envelope::RESPONSE:
      case igms::Envelope::ERROR: {
        Status status;
        if (e.kind() == igms::Envelope::ERROR) {
          status = Status::Error(
              e.error().code() == igms::ERROR_CODE_UNSPECIFIED ? igms::INTERNAL : e.error().code(),
              e.error().message());
        }
        RawDone done;
        {
          std::lock_guard calls(calls_mutex);
          if (auto it = pending.find(id); it != pending.end()) {
            done = std::move(it->second.done);
            pending.erase(it);
          }
        }
        if (done) {
          done(status, payload);
        } else if (auto s = subscriptions.find(id); s != subscriptions.end() && !status.ok()) {
          // The server refused the stream: don't ask again on reconnect.
          auto on_error = std::move(s->second.on_error);
          subscriptions.erase(s);
          spdlog::warn("{}: a subscription to {} was refused: {}", options.name, e.method(),
                       status.ToString());
          if (on_error) on_error(status);
        } else if (!status.ok()) {
          last_server_error = status.ToString();
          spdlog::warn("{}: {} says {}", options.name, Where(), last_server_error);
        }
        return;
      }
      case igms::Envelope::STREAM:
        if (auto s = subscriptions.find(id); s != subscriptions.end()) {
          s->second.on_message(payload, e.header().send_time_unix_ns());
        }
        return;
      default:
        spdlog::debug("{}: ignoring {} from server", options.name,
                      igms::Envelope::Kind_Name(e.kind()));
    }
  }

  // The connection is gone: fail what was in flight, keep what can be resent, retry.
  void Drop(const std::string& why) {
    ++generation;
    std::vector<RawDone> failed;
    {
      std::lock_guard lock(write_mutex);
      live = false;
      boost::system::error_code ignored;
      if (tls) tls->Shutdown();
      socket.close(ignored);
      out.clear();
      writing = false;
      std::lock_guard calls(calls_mutex);
      for (auto it = pending.begin(); it != pending.end();) {
        if (it->second.sent) {
          failed.push_back(std::move(it->second.done));
          it = pending.erase(it);
        } else {
          ++it;
        }
      }
    }
    connect_timer.cancel();
    heartbeat_timer.cancel();
    const std::string reason =
        why + (last_server_error.empty() ? "" : " (" + last_server_error + ")");
    const bool was_connected = [&] {
      std::lock_guard lock(state_mutex);
      return state == ConnectionState::kConnected;
    }();
    SetState(ConnectionState::kDisconnected, reason);
    if (was_connected) spdlog::warn("{}: lost {}: {}", options.name, Where(), reason);
    for (auto& done : failed) {
      done(Status::Error(igms::UNAVAILABLE, "connection to " + Where() + " lost: " + reason), "");
    }
    if (options.reconnect && !IsStopped()) {
      retry_timer.expires_after(backoff);
      backoff = std::min(backoff * 2, options.max_backoff);
      retry_timer.async_wait([self = shared_from_this()](boost::system::error_code ec) {
        if (!ec) self->Connect();
      });
    } else {
      // No reconnection: later calls fail at once with this reason instead of waiting out
      // their timeouts for a connection that will not come.
      gave_up = "not connected to " + Where() + ": " + reason;
      FailAll(gave_up);
    }
  }

  void FailAll(const std::string& why) {
    std::map<std::uint64_t, Pending> all;
    {
      std::lock_guard calls(calls_mutex);
      all = std::move(pending);
      pending.clear();
    }
    for (auto& [id, p] : all) {
      p.done(Status::Error(igms::UNAVAILABLE, why), "");
    }
  }

  // On the strand.
  void ArmDeadline(std::chrono::steady_clock::time_point when) {
    {
      std::lock_guard calls(calls_mutex);
      if (when >= deadline_armed) return;
      deadline_armed = when;
    }
    deadline_timer.expires_at(when);
    deadline_timer.async_wait([self = shared_from_this()](boost::system::error_code ec) {
      if (ec) return;
      {
        std::lock_guard calls(self->calls_mutex);
        self->deadline_armed = std::chrono::steady_clock::time_point::max();
      }
      self->ExpireCalls();
    });
  }

  void ExpireCalls() {
    const auto now = std::chrono::steady_clock::now();
    auto next = std::chrono::steady_clock::time_point::max();
    std::vector<std::pair<RawDone, Status>> expired;
    std::unique_lock calls(calls_mutex);
    for (auto it = pending.begin(); it != pending.end();) {
      if (it->second.deadline <= now) {
        const auto& p = it->second;
        expired.emplace_back(
            std::move(it->second.done),
            Status::Error(igms::TIMEOUT, p.method + ": no " + (p.sent ? "answer" : "connection") +
                                             " from " + Where() + " within " +
                                             std::to_string(p.timeout.count()) + " ms"));
        it = pending.erase(it);
      } else {
        next = std::min(next, it->second.deadline);
        ++it;
      }
    }
    calls.unlock();
    if (next != std::chrono::steady_clock::time_point::max()) ArmDeadline(next);
    for (auto& [done, status] : expired) done(status, "");
  }

  bool IsStopped() {
    std::lock_guard lock(state_mutex);
    return stopped;
  }
};

Client::Client(asio::io_context& io, ClientOptions options)
    : impl_(std::make_shared<Impl>(io, std::move(options))) {}

Client::~Client() { Stop(); }

void Client::Start() {
  const TlsOptions tls = impl_->options.tls ? *impl_->options.tls : TlsOptions::ForProcess();
  if (tls.enabled) {
    try {
      impl_->tls_context = std::make_shared<const TlsContext>(tls, TlsContext::Role::kClient);
      const std::string warning = impl_->tls_context->ExpiryWarning(std::chrono::hours(24 * 7));
      if (!warning.empty()) spdlog::warn("{}: {}", impl_->options.name, warning);
    } catch (const std::exception& e) {
      impl_->tls_error = std::string("TLS: ") + e.what();
    }
  }
  asio::post(impl_->strand, [impl = impl_] { impl->Connect(); });
}

void Client::Stop() {
  {
    std::lock_guard lock(impl_->state_mutex);
    if (impl_->stopped) return;
    impl_->stopped = true;
  }
  asio::post(impl_->strand, [impl = impl_] {
    ++impl->generation;
    {
      std::lock_guard lock(impl->write_mutex);
      impl->live = false;
      boost::system::error_code ignored;
      impl->socket.close(ignored);
    }
    impl->resolver.cancel();
    impl->connect_timer.cancel();
    impl->retry_timer.cancel();
    impl->heartbeat_timer.cancel();
    impl->deadline_timer.cancel();
    impl->FailAll("client stopped");
    impl->subscriptions.clear();
    impl->SetState(ConnectionState::kDisconnected, "client stopped");
  });
}

bool Client::connected() const {
  std::lock_guard lock(impl_->state_mutex);
  return impl_->state == ConnectionState::kConnected;
}

void Client::OnStateChange(std::function<void(ConnectionState, const std::string&)> fn) {
  asio::post(impl_->strand, [impl = impl_, fn = std::move(fn)] { impl->on_state = fn; });
}

bool Client::WaitConnected(std::chrono::milliseconds timeout) {
  std::unique_lock lock(impl_->state_mutex);
  return impl_->state_cv.wait_for(lock, timeout,
                                  [&] { return impl_->state == ConnectionState::kConnected; });
}

std::uint64_t Client::NextId() { return impl_->next_id.fetch_add(1); }

std::string Client::FrameFor(igms::Envelope::Kind kind, std::uint64_t id, const std::string& method,
                             const google::protobuf::MessageLite& payload) const {
  std::string frame;
  AppendFrame(impl_->Make(kind, id, method), payload, &frame);
  return frame;
}

void Client::CallRaw(const std::string& method, std::string payload,
                     std::chrono::milliseconds timeout, RawDone done) {
  const auto id = NextId();
  auto e = impl_->Make(igms::Envelope::REQUEST, id, method);
  e.set_payload(std::move(payload));
  SendCall(id, method, EncodeFrame(e), timeout, std::move(done));
}

void Client::SendCall(std::uint64_t id, const std::string& method, std::string frame,
                      std::chrono::milliseconds timeout, RawDone done) {
  Impl::Pending p;
  p.method = method;
  p.timeout = timeout;
  p.deadline = std::chrono::steady_clock::now() + timeout;
  const auto when = p.deadline;
  bool arm = false;
  {
    // The fast path: connected, so register the call and write it from this thread.
    std::unique_lock lock(impl_->write_mutex);
    if (impl_->live) {
      p.done = std::move(done);
      p.sent = true;
      {
        std::lock_guard calls(impl_->calls_mutex);
        arm = when < impl_->deadline_armed;
        impl_->pending.emplace(id, std::move(p));
      }
      if (impl_->tls_context) {
        // TLS: written from here when the stream is idle, else by the strand.
        if (!impl_->writing && impl_->tls && impl_->tls->TryDirectWrite(frame)) {
          impl_->sent_since_heartbeat = true;
        } else if (impl_->QueueLocked(std::move(frame))) {
          asio::post(impl_->strand,
                     [impl = impl_, gen = impl_->live_generation] { impl->WriteNext(gen); });
        }
      } else if (!impl_->writing) {  // (a queued frame always has a writer)
        impl_->SendDirectLocked(std::move(frame));
      } else {
        impl_->out.push_back(std::move(frame));  // the writer in flight takes it next
      }
      lock.unlock();
      if (arm) {
        // Earlier than the deadline timer's: move it (rare; timeouts are mostly alike).
        asio::post(impl_->strand, [impl = impl_, when] { impl->ArmDeadline(when); });
      }
      return;
    }
  }
  // Not connected (or stopped): the strand decides, in order with connection events.
  asio::post(impl_->strand, [impl = impl_, id, p = std::move(p), frame = std::move(frame),
                             done = std::move(done)]() mutable {
    if (impl->IsStopped()) {
      done(Status::Error(igms::UNAVAILABLE, "client stopped"), "");
      return;
    }
    if (!impl->gave_up.empty()) {
      done(Status::Error(igms::UNAVAILABLE, impl->gave_up), "");
      return;
    }
    p.done = std::move(done);
    const auto deadline = p.deadline;
    bool start_writer = false;
    {
      std::lock_guard lock(impl->write_mutex);
      std::lock_guard calls(impl->calls_mutex);
      if (impl->live) {  // connected since the caller looked
        p.sent = true;
        impl->pending.emplace(id, std::move(p));
        start_writer = impl->QueueLocked(std::move(frame));
      } else {  // sent by OnConnected
        p.frame = std::move(frame);
        impl->pending.emplace(id, std::move(p));
      }
    }
    if (start_writer) impl->WriteNext(impl->generation);
    impl->ArmDeadline(deadline);
  });
}

std::uint64_t Client::SubscribeRaw(const std::string& method, std::string payload,
                                   RawStream on_message,
                                   std::function<void(const Status&)> on_error) {
  const auto id = NextId();
  auto e = impl_->Make(igms::Envelope::SUBSCRIBE, id, method);
  e.set_payload(std::move(payload));
  SendSubscribe(id, EncodeFrame(e), std::move(on_message), std::move(on_error));
  return id;
}

void Client::SendSubscribe(std::uint64_t id, std::string frame, RawStream on_message,
                           std::function<void(const Status&)> on_error) {
  asio::post(impl_->strand,
             [impl = impl_, id, frame = std::move(frame), on_message = std::move(on_message),
              on_error = std::move(on_error)]() mutable {
               if (impl->IsStopped()) return;
               auto& s = impl->subscriptions[id];
               s.frame = std::move(frame);
               s.on_message = std::move(on_message);
               s.on_error = std::move(on_error);
               const bool is_connected = [&] {
                 std::lock_guard lock(impl->state_mutex);
                 return impl->state == ConnectionState::kConnected;
               }();
               if (is_connected) impl->WriteFrame(s.frame);
             });
}

void Client::Unsubscribe(std::uint64_t id) {
  asio::post(impl_->strand, [impl = impl_, id] {
    if (impl->subscriptions.erase(id) == 0) return;
    bool is_connected;
    {
      std::lock_guard lock(impl->state_mutex);
      is_connected = impl->state == ConnectionState::kConnected;
    }
    if (is_connected) impl->Write(impl->Make(igms::Envelope::UNSUBSCRIBE, id, ""));
  });
}

}  // namespace igms::net
