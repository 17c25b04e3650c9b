// The client's connection: connecting (with TLS, the handshake and greeting), the heartbeat,
// and on a loss, failing the calls in flight and reconnecting with back-off.
#include "common/net/client_impl.h"

namespace igms::net {

void Client::Impl::SetState(ConnectionState s, const std::string& why) {
  {
    std::lock_guard lock(state_mutex);
    state = s;
  }
  state_cv.notify_all();
  if (on_state) on_state(s, why);
}

void Client::Impl::Connect() {
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
                                       const tcp::resolver::results_type& results) {
        if (gen != self->generation) return;
        if (ec) {
          self->Drop("cannot resolve " + self->options.host + ": " + ec.message());
          return;
        }
        asio::async_connect(
            self->socket, results, [self, gen](boost::system::error_code ec, const tcp::endpoint&) {
              if (gen != self->generation) return;
              self->connect_timer.cancel();
              if (ec) {
                self->Drop(ec == asio::error::operation_aborted ? "connect timed out"
                                                                : ec.message());
                return;
              }
              self->OnConnected();
            });
      });
}

void Client::Impl::OnConnected() {
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

void Client::Impl::OnSecured() {
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

void Client::Impl::Heartbeat(std::uint64_t gen) {
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

void Client::Impl::Drop(const std::string& why) {
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

void Client::Impl::FailAll(const std::string& why) {
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

}  // namespace igms::net
