// The client base: one TCP connection to one IGMS server, shared by every caller.
//
//  - Connects with a timeout and, unless told not to, reconnects by itself with backoff
//    (100 ms doubling to 5 s); every active subscription is sent again after a reconnect.
//  - Call: a request matched to its response by correlation id, with its own timeout. A call
//    made while disconnected waits for the connection until its timeout; a call in flight
//    when the connection drops fails at once with UNAVAILABLE.
//  - Subscribe: a server-pushed stream; the callback runs on the client's network thread.
//    Hand messages to another thread (a render loop) with a Mailbox (common/net/mailbox.h).
//  - Sends HELLO (protocol version, token) first and a HEARTBEAT when idle, so the server's
//    idle timeout only closes peers that are really gone.
// Thread-safe: every method may be called from any thread. Callbacks run on the io_context
// given to the constructor, which the owner runs (on one thread or several).
#pragma once

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <string>

#include "common/net/status.h"

namespace igms::net {

struct ClientOptions {
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;
  std::string name = "client";  // sent in every header, for the server's logs
  std::string token;            // the lab token, if the lab has one
  std::chrono::milliseconds connect_timeout{2000};
  std::chrono::milliseconds heartbeat_interval{5000};
  std::chrono::milliseconds max_backoff{5000};
  std::size_t max_frame_bytes = 4u << 20;
  bool reconnect = true;
};

enum class ConnectionState { kConnecting, kConnected, kDisconnected };

class Client {
 public:
  using RawDone = std::function<void(const Status&, const std::string& payload)>;
  using RawStream = std::function<void(const std::string& payload, std::int64_t send_time_ns)>;

  Client(boost::asio::io_context& io, ClientOptions options);
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  void Start();
  // Closes the connection; pending calls fail with UNAVAILABLE. No reconnection after it.
  void Stop();
  bool connected() const;
  // Called on every change of connection state, with a reason for a person.
  void OnStateChange(std::function<void(ConnectionState, const std::string&)> fn);
  // Blocks until connected or the timeout passes. Never from the io thread.
  bool WaitConnected(std::chrono::milliseconds timeout);

  // Untyped forms, for generic tools such as igmsctl.
  void CallRaw(const std::string& method, std::string payload, std::chrono::milliseconds timeout,
               RawDone done);
  std::uint64_t SubscribeRaw(const std::string& method, std::string payload, RawStream on_message,
                             std::function<void(const Status&)> on_error = nullptr);
  void Unsubscribe(std::uint64_t id);

  template <class Resp, class Req>
  void Call(const std::string& method, const Req& req, std::chrono::milliseconds timeout,
            std::function<void(Result<Resp>)> done) {
    CallRaw(method, req.SerializeAsString(), timeout,
            [done = std::move(done)](const Status& status, const std::string& payload) {
              Result<Resp> r;
              r.status = status;
              if (status.ok() && !r.value.ParseFromString(payload)) {
                r.status = Status::Error(igms::BAD_REQUEST,
                                         "response is not a " + r.value.GetTypeName());
              }
              done(std::move(r));
            });
  }

  template <class Resp, class Req>
  Result<Resp> CallSync(const std::string& method, const Req& req,
                        std::chrono::milliseconds timeout) {
    auto promise = std::make_shared<std::promise<Result<Resp>>>();
    auto future = promise->get_future();
    Call<Resp>(method, req, timeout, [promise](Result<Resp> r) { promise->set_value(std::move(r)); });
    return future.get();
  }

  template <class Msg, class Req>
  std::uint64_t Subscribe(const std::string& method, const Req& req,
                          std::function<void(const Msg&)> on_message,
                          std::function<void(const Status&)> on_error = nullptr) {
    return SubscribeRaw(
        method, req.SerializeAsString(),
        [on_message = std::move(on_message)](const std::string& payload, std::int64_t) {
          Msg m;
          if (m.ParseFromString(payload)) on_message(m);
        },
        std::move(on_error));
  }

  struct Impl;

 private:
  std::shared_ptr<Impl> impl_;
};

}  // namespace igms::net
