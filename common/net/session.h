// One connected client of a Server. Internal to common/net.
#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <deque>
#include <memory>
#include <mutex>
#include <set>
#include <string>

#include "common/net/read_buffer.h"
#include "common/net/server.h"
#include "common/net/tls.h"

namespace igms::net {

class Session : public std::enable_shared_from_this<Session> {
 public:
  using Strand = boost::asio::strand<boost::asio::io_context::executor_type>;
  Session(boost::asio::ip::tcp::socket socket, std::shared_ptr<Server::Impl> server);

  void Start();
  // Thread-safe: queue a frame; latest_only replaces a queued, unwritten frame of the same
  // stream. Returns false if the session is closing.
  bool Send(std::string frame, std::uint64_t latest_only_key);
  // Thread-safe: close the socket and forget every subscription.
  void Close(const std::string& reason);
  bool SubscriptionOpen(std::uint64_t id);
  const std::string& peer() const { return peer_; }
  // On the session's thread (a handler called from Dispatch): who this client is.
  Caller Describe();
  bool closed();

 private:
  struct Outgoing {
    std::string bytes;
    std::uint64_t stream_id = 0;  // non-zero for a latest-only stream frame
  };
  void ReadMore();
  void OnRead(const std::string& error, std::size_t n);
  void OnHandshake(const std::string& error);
  bool LooksLikeTls() const;
  void OnFrame(std::string_view frame);
  void Dispatch(igms::Envelope& envelope, std::string_view payload);
  void SendError(std::uint64_t id, const std::string& method, igms::ErrorCode code,
                 const std::string& message, bool close_after);
  void WriteNext();
  void WriteNextTls();
  // With mutex_ held: true when there is nothing to write (closed, or the queue empty, which
  // ends the writing and, after a rejection, closes the session).
  bool NothingToWriteLocked();
  bool Permitted(std::uint64_t id, const std::string& method);
  void ArmIdleTimer();

  boost::asio::ip::tcp::socket socket_;
  std::shared_ptr<Server::Impl> server_;
  boost::asio::steady_timer idle_timer_;
  std::chrono::steady_clock::time_point last_activity_ = std::chrono::steady_clock::now();
  std::string peer_;
  std::string address_;  // the peer's address alone, for the failure limiter
  std::shared_ptr<TlsStream> tls_;
  std::string peer_name_;    // the CN of the peer's certificate, with TLS
  std::string endpoint_;     // "address:port", without the certificate's name
  std::string client_name_;  // the sender its HELLO (or its first request) named
  bool first_read_ = true;
  ReadBuffer in_;
  bool authenticated_ = false;
  bool close_after_write_ = false;

  std::mutex mutex_;  // guards everything below
  bool closed_ = false;
  std::deque<Outgoing> queue_;
  std::size_t queued_bytes_ = 0;
  bool writing_ = false;
  std::set<std::uint64_t> subscriptions_;
};

}  // namespace igms::net
