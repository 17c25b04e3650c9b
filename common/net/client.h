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
//  - With TLS (ClientOptions::tls), a TLS 1.3 handshake with this process's certificate
//    comes before HELLO; a refusal (by either side) is the reason the connection reports.
// Thread-safe: every method may be called from any thread. Callbacks run on the io_context
// given to the constructor, which the owner runs (on one thread or several).
#pragma once

#include <google/protobuf/message_lite.h>

#include <atomic>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <thread>

#include "common/net/status.h"
#include "common/net/tls.h"

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
  // nullopt: the process's lab settings (TlsOptions::ForProcess: plain unless lab.tls: on).
  // With TLS the server's certificate must be the lab authority's and name `host`.
  std::optional<TlsOptions> tls;
};

enum class ConnectionState { kConnecting, kConnected, kDisconnected };

class Client {
 public:
  // Payload views are valid only during the callback.
  using RawDone = std::function<void(const Status&, std::string_view payload)>;
  using RawStream = std::function<void(std::string_view payload, std::int64_t send_time_ns)>;

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
    // The request is framed here, on the caller's thread, in one copy.
    const std::uint64_t id = NextId();
    SendCall(id, method, FrameFor(igms::Envelope::REQUEST, id, method, req), timeout,
             [done = std::move(done)](const Status& status, std::string_view payload) {
               Result<Resp> r;
               r.status = status;
               if (status.ok() &&
                   !r.value.ParseFromArray(payload.data(), static_cast<int>(payload.size()))) {
                 r.status =
                     Status::Error(igms::BAD_REQUEST, "response is not a " + r.value.GetTypeName());
               }
               done(std::move(r));
             });
  }

  template <class Resp, class Req>
  Result<Resp> CallSync(const std::string& method, const Req& req,
                        std::chrono::milliseconds timeout) {
    // An atomic flag rather than a promise: its wait spins briefly before sleeping, so an
    // answer that comes back within microseconds does not cost the caller a futex sleep.
    struct Slot {
      std::atomic<bool> ready{false};
      Result<Resp> result;
    };
    auto slot = std::make_shared<Slot>();
    Call<Resp>(method, req, timeout, [slot](Result<Resp> r) {
      slot->result = std::move(r);
      slot->ready.store(true, std::memory_order_release);
      slot->ready.notify_one();
    });
    // Most answers on a lab network come back within tens of microseconds: yield the CPU
    // for that long (other threads run meanwhile) before sleeping on the flag.
    const auto spin_until = std::chrono::steady_clock::now() + std::chrono::microseconds(50);
    while (!slot->ready.load(std::memory_order_acquire) &&
           std::chrono::steady_clock::now() < spin_until) {
      std::this_thread::yield();
    }
    slot->ready.wait(false, std::memory_order_acquire);
    return std::move(slot->result);
  }

  template <class Msg, class Req>
  std::uint64_t Subscribe(const std::string& method, const Req& req,
                          std::function<void(const Msg&)> on_message,
                          const std::function<void(const Status&)>& on_error = nullptr) {
    const std::uint64_t id = NextId();
    SendSubscribe(
        id, FrameFor(igms::Envelope::SUBSCRIBE, id, method, req),
        [on_message = std::move(on_message)](std::string_view payload, std::int64_t) {
          Msg m;
          if (m.ParseFromArray(payload.data(), static_cast<int>(payload.size()))) on_message(m);
        },
        on_error);
    return id;
  }

  // The pieces the typed calls are made of.
  std::uint64_t NextId();
  std::string FrameFor(igms::Envelope::Kind kind, std::uint64_t id, const std::string& method,
                       const google::protobuf::MessageLite& payload) const;
  void SendCall(std::uint64_t id, const std::string& method, std::string frame,
                std::chrono::milliseconds timeout, RawDone done);
  void SendSubscribe(std::uint64_t id, std::string frame, RawStream on_message,
                     std::function<void(const Status&)> on_error);

  struct Impl;

 private:
  std::shared_ptr<Impl> impl_;
};

}  // namespace igms::net
