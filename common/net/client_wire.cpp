// The client's frames: the write queue (from the caller's thread when it can, else the
// strand), reading and dispatching what the server sends, and the calls' deadlines.
#include "common/net/client_impl.h"

namespace igms::net {

void Client::Impl::WriteFrame(std::string frame) {
  std::unique_lock lock(write_mutex);
  if (!QueueLocked(std::move(frame))) return;
  lock.unlock();
  WriteNext(generation);
}

bool Client::Impl::QueueLocked(std::string frame) {
  out.push_back(std::move(frame));
  sent_since_heartbeat = true;
  if (writing) return false;
  writing = true;
  return true;
}

void Client::Impl::WriteNext(std::uint64_t gen) {
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

void Client::Impl::SendDirectLocked(std::string frame) {
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
  asio::post(strand, [self = shared_from_this(), gen = live_generation] { self->WriteNext(gen); });
}

void Client::Impl::Read(std::uint64_t gen) {
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

void Client::Impl::OnRead(std::uint64_t gen, const std::string& error, std::size_t n) {
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

void Client::Impl::OnEnvelope(igms::Envelope& e, std::string_view payload) {
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

void Client::Impl::ArmDeadline(std::chrono::steady_clock::time_point when) {
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

void Client::Impl::ExpireCalls() {
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

}  // namespace igms::net
