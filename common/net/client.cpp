// The client's interface: starting and stopping it, and calls and subscriptions from any
// thread (client_impl.h says where the rest is).
#include "common/net/client_impl.h"

namespace igms::net {

Client::Client(asio::io_context& io, ClientOptions options)
    : impl_(std::make_shared<Impl>(io, std::move(options))) {}

Client::~Client() {
  try {
    Stop();
  } catch (const std::exception& e) {  // a destructor must not throw: say so and go on
    spdlog::error("{}: cannot stop the client: {}", impl_->options.name, e.what());
  }
}

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
