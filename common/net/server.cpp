// The server: methods and streams registered, the acceptor started and stopped, and TLS
// reloaded on SIGHUP (server_impl.h; each connection's session is in session.cpp).
#include "common/net/server_impl.h"

namespace igms::net {

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
              Reply<igms::PingResponse>(std::move(s), id, "igms.Server.Ping")(Status::Ok(), r);
            });
}

Server::~Server() {
  // Stop locks, posts and waits; should either fail, the server goes without its orderly
  // stop rather than the process with it.
  try {
    Stop();
  } catch (const std::exception& e) {
    spdlog::error("{}: stopping the server: {}", options_.name, e.what());
  }
}

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

}  // namespace igms::net
