// Client's inside, shared by its source files: the connection with its write queue, the calls
// in flight and the subscriptions (client.cpp: calls and subscriptions from any thread;
// client_connection.cpp: connecting, the heartbeat, dropping and reconnecting;
// client_wire.cpp: writing frames, reading and dispatching them, and the calls' deadlines).
// Not part of the interface: client.h is.
#pragma once

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
#include "common/net/client.h"
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

  void SetState(ConnectionState s, const std::string& why);

  std::string Where() const { return options.host + ":" + std::to_string(options.port); }

  igms::Envelope Make(igms::Envelope::Kind kind, std::uint64_t id, const std::string& method) {
    igms::Envelope e = MakeEnvelope(kind, id, method);
    e.mutable_header()->set_sender(options.name);
    return e;
  }

  // On the strand.
  void Write(const igms::Envelope& e) { WriteFrame(EncodeFrame(e)); }
  void WriteFrame(std::string frame);
  // Queues a frame; true when the caller must start the writer (WriteNext).
  bool QueueLocked(std::string frame);

  // On the strand, with `writing` set: sends the queue one frame after another (with TLS,
  // all of it, encrypted, in one write).
  void WriteNext(std::uint64_t gen);

  // On the caller's thread, with write_mutex held, live set and nothing in flight: writes
  // what the kernel takes now; the rest (if any) goes to the strand's writer.
  void SendDirectLocked(std::string frame);
  void Connect();
  void OnConnected();

  // Connected, and with TLS past the handshake.
  void OnSecured();
  void Heartbeat(std::uint64_t gen);
  void Read(std::uint64_t gen);
  void OnRead(std::uint64_t gen, const std::string& error, std::size_t n);
  void OnEnvelope(igms::Envelope& e, std::string_view payload);

  // The connection is gone: fail what was in flight, keep what can be resent, retry.
  void Drop(const std::string& why);
  void FailAll(const std::string& why);

  // On the strand.
  void ArmDeadline(std::chrono::steady_clock::time_point when);
  void ExpireCalls();

  bool IsStopped() {
    std::lock_guard lock(state_mutex);
    return stopped;
  }
};

}  // namespace igms::net
