// Server's inside, shared by server.cpp (the acceptor, TLS reloads, the interface) and
// session.cpp (one connection's session, which reaches back for the methods, the options and
// the failure limiter). Not part of the interface: server.h is.
#pragma once

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
#include "common/net/server.h"
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
                             std::chrono::duration<double>(self->options.failures.block).count());
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

}  // namespace igms::net
