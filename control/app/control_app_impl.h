// ControlApp's inside, shared by its source files: the peers' links, the network loop and its
// timers, and the session they feed (control_app.cpp: the session and the timers;
// control_app_effects.cpp: what the session asks for; control_app_peers.cpp: connecting and
// checking the peers). Not part of the interface: control_app.h is.
#pragma once

#include <spdlog/spdlog.h>

#include <boost/asio.hpp>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <condition_variable>
#include <future>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "common/base/clock.h"
#include "common/net/client.h"
#include "control/app/control_app.h"
#include "igms/common.pb.h"

namespace igms::control {

namespace asio = boost::asio;

namespace app_detail {

using std::chrono::milliseconds;

inline constexpr const char* kPing = "igms.Server.Ping";

// The service name of a peer's methods.
inline std::string Service(Peer peer) {
  switch (peer) {
    case Peer::kVideo:
      return "igms.video.VideoService";
    case Peer::kObject:
      return "igms.object.ObjectService";
    case Peer::kSound:
      return "igms.sound.SoundService";
    case Peer::kPlatform:
      return "igms.devices.PlatformService";
    case Peer::kViewer:
      return "igms.devices.ViewerService";
    case Peer::kJoystick:
      return "igms.devices.JoystickService";
    case Peer::kVoice:
      return "igms.devices.VoiceService";
    case Peer::kRanger:
      return "igms.devices.RangerService";
  }
  return "";
}

inline bool LinkGood(devices::LinkState state) {
  return state == devices::CONNECTED || state == devices::REPLAYING;
}

inline CallError ToCallError(const net::Status& status) {
  return CallError{status.code, status.message};
}

inline NoticeLevel LevelOf(spdlog::level::level_enum level) {
  if (level >= spdlog::level::err) return NoticeLevel::kError;
  if (level == spdlog::level::warn) return NoticeLevel::kWarning;
  return NoticeLevel::kInfo;
}

}  // namespace app_detail

struct ControlApp::Impl : std::enable_shared_from_this<Impl> {
  struct Link {
    Peer peer = Peer::kVideo;
    PeerAddress address;
    std::unique_ptr<net::Client> client;
    bool up = false;        // as last told to the session
    bool checking = false;  // a check is in flight
    bool subscribed = false;
    std::string refused;  // why the last check refused it (logged once per reason)
    ServerVersion version;
    devices::LinkState link_state = devices::LINK_STATE_UNSPECIFIED;
  };

  ControlAppOptions options;
  std::unique_ptr<GeometricDatabase> database;
  std::unique_ptr<Session> session;

  asio::io_context io;
  std::optional<asio::executor_work_guard<asio::io_context::executor_type>> work;
  std::thread thread;
  std::promise<void> loop_ended;  // set when io.run() returns
  asio::steady_timer tick_timer{io};
  asio::steady_timer health_timer{io};

  std::map<Peer, Link> links;
  sound::ListBankResponse bank;
  // The sound server's refusals not warned of, and the time of the last warning.
  int sound_refusals = 0;
  std::chrono::steady_clock::time_point sound_warned{};
  video::OverlaySettings overlay;
  bool started = false;  // the StartEvent has been handled
  // Set by Shutdown: the timers no longer re-arm. Cancelling them is not enough, as a timer
  // that expired while the loop was busy has its handler queued already, and cancel() cannot
  // take it back: it would run with success and arm the timer again, for ever, so io.run()
  // never ran out of work (the exit hang of issue 20).
  bool shutting_down = false;
  int start_checks_pending = 0;
  std::vector<PeerReport> start_reports;
  std::map<uint64_t, int64_t> locate_sent_ns;  // call -> when sent, for the round trip
  double last_round_trip_ms = 0;
  std::map<uint64_t, int64_t> database_ids;  // session id -> database id

  ViewBoard board;
  SessionView view;
  uint64_t notices = 0;

  std::mutex exit_mutex;
  std::condition_variable exited;
  std::optional<int> exit_code;

  Link* LinkOf(Peer peer) {
    auto it = links.find(peer);
    return it == links.end() ? nullptr : &it->second;
  }
  bool Up(Peer peer) {
    Link* link = LinkOf(peer);
    return link && link->up;
  }

  // ---- the session ----

  void Handle(const Event& event);
  void Publish();
  void Note(spdlog::level::level_enum level, std::string text);
  void Finish(int code);

  // ---- effects ----

  void Execute(const SetOrientationEffect& e);
  void Execute(const GrabEffect& e);
  void Execute(const RangeEffect& e);
  void Execute(const LocateEffect& e);
  void Execute(const SetOperatorStateEffect& e);
  void Play(const std::string& key, sound::Priority priority);
  void Execute(const PlaySoundEffect& e);
  void Execute(const SpeakFailureEffect& e);
  std::vector<ServerVersion> Servers();
  void Execute(const StoreModelEffect& e);
  void Execute(const RemoveModelEffect& e);
  void ModelsChanged();
  void Execute(const RestoreModelEffect& e);

  // The session undoes its own latest model change, which is the database's latest (one
  // writer): the database's undo records it as such.
  void UndoInDatabase(uint64_t session_id);
  void Execute(const DisplayEffect&);
  void Execute(const NoticeEffect& e);
  void Execute(const ExitEffect& e);

  // A call to a peer; a peer that is down (or not configured) is answered at once with
  // UNAVAILABLE, after the event being handled.
  template <class Resp, class Req>
  void CallPeer(Peer peer, const std::string& method, const Req& request,
                std::chrono::milliseconds timeout, std::function<void(net::Result<Resp>)> done) {
    Link* link = LinkOf(peer);
    if (!link || !link->up) {
      net::Result<Resp> r;
      r.status = net::Status::Error(
          UNAVAILABLE,
          std::string(PeerName(peer)) +
              (link ? " (" + link->address.ToString() + ") is down" : " is not in the lab file"));
      asio::post(io, [done = std::move(done), r = std::move(r)]() mutable { done(std::move(r)); });
      return;
    }
    link->client->Call<Resp>(app_detail::Service(peer) + "." + method, request, timeout,
                             [self = shared_from_this(), done = std::move(done)](
                                 net::Result<Resp> r) mutable { done(std::move(r)); });
  }

  // ---- peers ----

  void Connect();
  void StartSession();
  void OnConnection(Peer peer, net::ConnectionState state, const std::string& why);

  // Checks a peer that has (re)connected; up, it is reported to the session.
  void CheckAndReport(Link& link);

  // Ping, then what this kind of peer must show (thesis 2.4's start-up checks).
  void Check(Link& link, std::function<void(PeerReport)> done);
  void CheckService(Peer peer, const std::function<void(bool, std::string)>& finish);

  // A peer just reported up: its streams, and the voice daemon's news filter.
  void AfterUp(Link& link);

  // Once per peer: the client subscribes again by itself after a reconnection.
  void Subscribe(Link& link);

  // ---- timers ----

  void Tick();

  // 1 Hz: each daemon's serial link, and every peer not up yet that is connected.
  void Health();
  void Shutdown();
};

}  // namespace igms::control
