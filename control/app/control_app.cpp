#include "control/app/control_app.h"

#include <spdlog/spdlog.h>

#include <boost/asio.hpp>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/steady_timer.hpp>
#include <condition_variable>
#include <future>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "common/base/clock.h"
#include "common/net/client.h"
#include "igms/common.pb.h"

namespace igms::control {
namespace {

namespace asio = boost::asio;
using std::chrono::milliseconds;

constexpr const char* kPing = "igms.Server.Ping";

// The service name of a peer's methods.
std::string Service(Peer peer) {
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

bool LinkGood(devices::LinkState state) {
  return state == devices::CONNECTED || state == devices::REPLAYING;
}

CallError ToCallError(const net::Status& status) { return CallError{status.code, status.message}; }

NoticeLevel LevelOf(spdlog::level::level_enum level) {
  if (level >= spdlog::level::err) return NoticeLevel::kError;
  if (level == spdlog::level::warn) return NoticeLevel::kWarning;
  return NoticeLevel::kInfo;
}

}  // namespace

bool ControlAppOptions::Check(std::string* error) const {
  auto fail = [&](std::string why) {
    if (error) *error = std::move(why);
    return false;
  };
  if (!session.Check(error)) return false;
  for (const auto& [peer, address] : peers) {
    if (address.host.empty() || address.port == 0) {
      return fail("processes." + address.name + ": needs a host and a port for the " +
                  std::string(PeerName(peer)) + " peer");
    }
  }
  if (call_timeout.count() <= 0 || grab_timeout.count() <= 0 || locate_timeout.count() <= 0 ||
      range_timeout.count() <= 0) {
    return fail("call timeouts must be positive");
  }
  if (tick.count() <= 0 || health_period.count() <= 0) {
    return fail("the tick and the health period must be positive");
  }
  return true;
}

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
  int sound_refusals = 0;
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

  void Handle(const Event& event) {
    if (exit_code) return;
    const Effects effects = session->Handle(event);
    for (const Effect& effect : effects) std::visit([&](const auto& e) { Execute(e); }, effect);
    // Ticks come 50 times a second and mostly change nothing the display shows.
    if (!effects.empty() || !std::holds_alternative<TickEvent>(event)) Publish();
  }

  void Publish() {
    view.version++;
    if (session->mode() != view.mode || view.version == 1) {
      spdlog::info("mode: {}", ModeName(session->mode()));
    }
    view.mode = session->mode();
    view.viewer = session->viewer();
    for (Peer p : kAllPeers) view.peer_up[static_cast<int>(p)] = session->peer_up(p);
    view.wireframe = session->wireframe();
    view.pointer = session->pointer();
    view.marks = session->marks();
    view.models = session->models();
    view.frozen = session->frozen();
    view.range = session->range();
    view.failure_detail = session->failure_detail();
    view.platform_target = session->platform_target();
    board.Publish(view);
    if (options.view_published) options.view_published(view, NowNs());
  }

  void Note(spdlog::level::level_enum level, std::string text) {
    spdlog::log(level, "{}", text);
    view.notices.push_back(NoticeLine{LevelOf(level), std::move(text), ++notices});
    while (view.notices.size() > SessionView::kKeptNotices) view.notices.pop_front();
  }

  void Finish(int code) {
    {
      std::lock_guard lock(exit_mutex);
      if (exit_code) return;
      exit_code = code;
    }
    view.exit_code = code;
    board.Publish(view);
    exited.notify_all();
  }

  // ---- effects ----

  void Execute(const SetOrientationEffect& e) {
    devices::SetOrientationRequest request;
    request.set_yaw_ticks(e.ticks.yaw);
    request.set_pitch_ticks(e.ticks.pitch);
    request.set_roll_ticks(e.ticks.roll);
    request.set_steps_per_move(e.steps_per_move);
    request.set_take_control(e.take_control);
    CallPeer<devices::SetOrientationResponse>(
        Peer::kPlatform, "SetOrientation", request, options.call_timeout,
        [this, call = e.call](net::Result<devices::SetOrientationResponse> r) {
          SetOrientationReply reply{call, std::nullopt, NowNs()};
          if (!r.ok()) reply.error = ToCallError(r.status);
          Handle(reply);
        });
  }

  void Execute(const GrabEffect& e) {
    CallPeer<video::GrabResponse>(Peer::kVideo, "Grab", video::GrabRequest(), options.grab_timeout,
                                  [this, call = e.call](net::Result<video::GrabResponse> r) {
                                    GrabReply reply{call, {}, NowNs()};
                                    if (r.ok()) {
                                      reply.result = std::move(r.value);
                                    } else {
                                      reply.result = ToCallError(r.status);
                                    }
                                    Handle(reply);
                                  });
  }

  void Execute(const RangeEffect& e) {
    CallPeer<devices::RangerState>(Peer::kRanger, "Range", devices::RangeRequest(),
                                   options.range_timeout,
                                   [this, call = e.call](net::Result<devices::RangerState> r) {
                                     RangeReply reply{call, {}, NowNs()};
                                     if (r.ok()) {
                                       reply.result = std::move(r.value);
                                     } else {
                                       reply.result = ToCallError(r.status);
                                     }
                                     view.ranges_taken++;
                                     Handle(reply);
                                   });
  }

  void Execute(const LocateEffect& e) {
    locate_sent_ns[e.call] = NowNs();
    CallPeer<object::LocateResponse>(
        Peer::kObject, "Locate", e.request, options.locate_timeout,
        [this, call = e.call](net::Result<object::LocateResponse> r) {
          const int64_t now = NowNs();
          if (auto it = locate_sent_ns.find(call); it != locate_sent_ns.end()) {
            last_round_trip_ms = static_cast<double>(now - it->second) / 1e6;
            locate_sent_ns.erase(it);
          }
          LocateReply reply{call, {}, now};
          if (r.ok()) {
            if (!r.value.found()) view.locates_failed++;
            reply.result = std::move(r.value);
          } else {
            view.locates_failed++;
            reply.result = ToCallError(r.status);
          }
          Handle(reply);
        });
  }

  void Execute(const SetOperatorStateEffect& e) {
    if (!Up(Peer::kVoice)) return;
    devices::SetOperatorStateRequest request;
    request.set_state(e.state);
    CallPeer<devices::SetOperatorStateResponse>(
        Peer::kVoice, "SetOperatorState", request, options.call_timeout,
        [this, state = e.state](net::Result<devices::SetOperatorStateResponse> r) {
          if (!r.ok()) {
            Note(spdlog::level::warn, "voice grammar not set: " + r.status.ToString());
            return;
          }
          view.voice_grammar = state;
          Publish();
        });
  }

  void Play(const std::string& key, sound::Priority priority) {
    // A lost sound server never stops a session: while it is away nothing is played.
    if (!Up(Peer::kSound)) return;
    sound::PlayRequest request;
    request.set_key(key);
    request.set_priority(priority);
    CallPeer<sound::PlayResponse>(
        Peer::kSound, "Play", request, options.call_timeout,
        [this, key](net::Result<sound::PlayResponse> r) {
          // A session faster than speech (a script) fills the sound server's queue: say so
          // once per run of refusals, not for every cue.
          if (r.ok()) {
            sound_refusals = 0;
          } else if (sound_refusals++ == 0) {
            spdlog::warn(
                "sound '{}' not played: {} (further refusals logged at debug level "
                "until a sound plays)",
                key, r.status.ToString());
          } else {
            spdlog::debug("sound '{}' not played: {}", key, r.status.ToString());
          }
        });
  }

  void Execute(const PlaySoundEffect& e) { Play(e.key, e.priority); }

  void Execute(const SpeakFailureEffect& e) {
    const std::string key = FailureMessageKey(bank, e.reason);
    if (key.empty()) {
      if (Up(Peer::kSound)) {
        spdlog::warn("the sound bank has no message for {}", object::FailureReason_Name(e.reason));
      }
      return;
    }
    Play(key, sound::PRIORITY_NORMAL);
  }

  std::vector<ServerVersion> Servers() {
    std::vector<ServerVersion> servers;
    for (auto& [peer, link] : links) {
      if (!link.version.program.empty()) servers.push_back(link.version);
    }
    return servers;
  }

  void Execute(const StoreModelEffect& e) {
    if (!database) return;
    ModelRecord record =
        MakeModelRecord(e.provenance.grab, e.provenance.request, e.provenance.response,
                        options.calibration_hash, Servers(), last_round_trip_ms);
    auto id = database->AddModel(record);
    if (!id.ok()) {
      Note(spdlog::level::err,
           "model " + std::to_string(e.model.id) + " NOT stored in the database: " + id.error());
      return;
    }
    database_ids[e.model.id] = *id;
    view.models_stored++;
    ModelsChanged();
    Note(spdlog::level::info, "model " + std::to_string(e.model.id) + " stored in " +
                                  database->path() + " as id " + std::to_string(*id));
  }

  void Execute(const RemoveModelEffect& e) {
    if (!database) return;
    auto it = database_ids.find(e.id);
    if (it == database_ids.end()) {
      Note(spdlog::level::err, "model " + std::to_string(e.id) + " is not in the database");
      return;
    }
    if (e.undo) {
      UndoInDatabase(e.id);
      return;
    }
    auto change = database->RemoveModel(it->second);
    if (!change.ok()) return Note(spdlog::level::err, "removing model: " + change.error());
    ModelsChanged();
  }

  void ModelsChanged() {
    if (!options.models_changed) return;
    auto present = database->ListModels();
    if (!present.ok()) return Note(spdlog::level::err, "the database: " + present.error());
    options.models_changed(std::move(*present));
  }

  void Execute(const RestoreModelEffect& e) {
    if (database) UndoInDatabase(e.id);
  }

  // The session undoes its own latest model change, which is the database's latest (one
  // writer): the database's undo records it as such.
  void UndoInDatabase(uint64_t session_id) {
    auto change = database->Undo();
    if (!change.ok()) {
      Note(spdlog::level::err, "undo in the database: " + change.error());
      return;
    }
    ModelsChanged();
    if (change->model_id != database_ids[session_id]) {
      Note(spdlog::level::err, "undo in the database took back model id " +
                                   std::to_string(change->model_id) + ", not " +
                                   std::to_string(database_ids[session_id]));
    }
  }

  void Execute(const DisplayEffect&) {}  // the view carries the display mode

  void Execute(const NoticeEffect& e) {
    const auto level = e.level == NoticeLevel::kError     ? spdlog::level::err
                       : e.level == NoticeLevel::kWarning ? spdlog::level::warn
                                                          : spdlog::level::info;
    Note(level, e.text);
  }

  void Execute(const ExitEffect& e) {
    Note(spdlog::level::critical, e.message);
    Finish(e.code);
  }

  // A call to a peer; a peer that is down (or not configured) is answered at once with
  // UNAVAILABLE, after the event being handled.
  template <class Resp, class Req>
  void CallPeer(Peer peer, const std::string& method, const Req& request, milliseconds timeout,
                std::function<void(net::Result<Resp>)> done) {
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
    link->client->Call<Resp>(Service(peer) + "." + method, request, timeout,
                             [self = shared_from_this(), done = std::move(done)](
                                 net::Result<Resp> r) mutable { done(std::move(r)); });
  }

  // ---- peers ----

  void Connect() {
    for (const auto& [peer, address] : options.peers) {
      Link& link = links[peer];
      link.peer = peer;
      link.address = address;
      net::ClientOptions client;
      client.host = address.host;
      client.port = address.port;
      client.name = options.client_name;
      client.token = options.token;
      client.connect_timeout = milliseconds(1000);
      client.max_backoff = milliseconds(1000);  // a restarted peer is back within a second
      if (peer == Peer::kVideo) client.max_frame_bytes = 64u << 20;
      link.client = std::make_unique<net::Client>(io, client);
      link.client->OnStateChange(
          [weak = weak_from_this(), peer](net::ConnectionState state, const std::string& why) {
            // Already on the network thread.
            if (auto self = weak.lock()) self->OnConnection(peer, state, why);
          });
      link.client->Start();
    }
    // The start-up round: every configured peer checked at once.
    start_checks_pending = static_cast<int>(links.size());
    if (start_checks_pending == 0) return StartSession();
    for (auto& [peer, link] : links) {
      Check(link, [this](PeerReport report) {
        start_reports.push_back(std::move(report));
        if (--start_checks_pending == 0) StartSession();
      });
    }
  }

  void StartSession() {
    if (database) {
      auto stored = database->ListModels();
      if (!stored.ok()) {
        Note(spdlog::level::critical, "the database: " + stored.error());
        return Finish(1);
      }
      if (options.models_changed) options.models_changed(*stored);
      ModelsLoaded loaded;
      loaded.now_ns = NowNs();
      for (const StoredModel& s : *stored) {
        SessionModel m;
        m.id = static_cast<uint64_t>(s.id);
        m.type = s.record.type;
        m.cylinder = s.record.cylinder;
        m.box = s.record.box;
        database_ids[m.id] = s.id;
        // The grab's pose places a box's texture patch (a record without a grab: flat).
        const ModelProvenance& p = s.record.provenance;
        if (p.frame_id != 0) {
          loaded.grab_joints[m.id].assign(p.platform_pose.joints_rad().begin(),
                                          p.platform_pose.joints_rad().end());
        }
        loaded.models.push_back(std::move(m));
      }
      if (!loaded.models.empty()) {
        Note(spdlog::level::info, "continuing " + database->path() + ": " +
                                      std::to_string(loaded.models.size()) + " models");
      }
      Handle(loaded);
    }
    for (auto& report : start_reports) {
      if (Link* link = LinkOf(report.peer); link && report.up) {
        link->up = true;
        AfterUp(*link);
      }
    }
    started = true;
    Handle(StartEvent{start_reports, NowNs()});
    Tick();
    Health();
  }

  void OnConnection(Peer peer, net::ConnectionState state, const std::string& why) {
    Link* link = LinkOf(peer);
    if (!link || !started) return;
    if (state == net::ConnectionState::kConnected) {
      if (!link->up) CheckAndReport(*link);
      return;
    }
    if (state == net::ConnectionState::kDisconnected && link->up) {
      link->up = false;
      Handle(PeerDownEvent{peer, why.empty() ? "connection lost" : why, NowNs()});
    }
  }

  // Checks a peer that has (re)connected; up, it is reported to the session.
  void CheckAndReport(Link& link) {
    if (link.checking || link.up) return;
    Check(link, [this, peer = link.peer](PeerReport report) {
      Link* link = LinkOf(peer);
      if (!link || link->up || !report.up || !started) return;
      link->up = true;
      AfterUp(*link);
      Handle(PeerUpEvent{peer, NowNs()});
    });
  }

  // Ping, then what this kind of peer must show (thesis 2.4's start-up checks).
  void Check(Link& link, std::function<void(PeerReport)> done) {
    link.checking = true;
    const Peer peer = link.peer;
    auto finish = [this, peer, done = std::move(done)](bool up, std::string why) {
      Link* link = LinkOf(peer);
      link->checking = false;
      if (!up && why != link->refused) {
        spdlog::warn("{} ({}): {}", PeerName(peer), link->address.ToString(), why);
      }
      link->refused = up ? "" : why;
      done(PeerReport{peer, link->address.ToString(), up, up ? "" : why});
    };
    link.client->Call<PingResponse>(
        kPing, PingRequest(), options.call_timeout,
        [this, peer, finish](net::Result<PingResponse> r) {
          if (!r.ok()) return finish(false, "no answer to a ping: " + r.status.ToString());
          Link* link = LinkOf(peer);
          link->version = {link->address.name, r.value.program(), r.value.version()};
          CheckService(peer, finish);
        });
  }

  void CheckService(Peer peer, std::function<void(bool, std::string)> finish) {
    Link* link = LinkOf(peer);
    const std::string service = Service(peer);
    auto hash_refusal = [this](const std::string& theirs) -> std::string {
      if (theirs.empty() || options.calibration_hash.empty() ||
          theirs == options.calibration_hash) {
        return "";
      }
      return "its calibration (sha256 " + theirs.substr(0, 12) + "...) differs from ours (" +
             options.calibration_hash.substr(0, 12) + "...)";
    };
    if (IsDaemon(peer)) {
      link->client->Call<devices::LinkStatus>(
          service + ".Status", devices::GetStatusRequest(), options.call_timeout,
          [this, peer, finish](net::Result<devices::LinkStatus> r) {
            if (!r.ok()) return finish(false, "no status: " + r.status.ToString());
            LinkOf(peer)->link_state = r.value.state();
            if (!LinkGood(r.value.state())) {
              return finish(false, "its serial link is " +
                                       devices::LinkState_Name(r.value.state()) +
                                       (r.value.message().empty() ? "" : ": " + r.value.message()));
            }
            finish(true, "");
          });
      return;
    }
    switch (peer) {
      case Peer::kVideo:
        link->client->Call<video::StatusResponse>(
            service + ".GetStatus", video::StatusRequest(), options.call_timeout,
            [this, finish, hash_refusal](net::Result<video::StatusResponse> r) {
              if (!r.ok()) return finish(false, "no status: " + r.status.ToString());
              if (auto why = hash_refusal(r.value.calibration_sha256()); !why.empty()) {
                return finish(false, why);
              }
              LinkOf(Peer::kVideo)
                  ->client->Call<video::GetOverlayResponse>(
                      Service(Peer::kVideo) + ".GetOverlay", video::GetOverlayRequest(),
                      options.call_timeout,
                      [this, finish](net::Result<video::GetOverlayResponse> o) {
                        if (!o.ok()) return finish(false, "no overlay: " + o.status.ToString());
                        overlay = o.value.settings();
                        finish(true, "");
                      });
            });
        return;
      case Peer::kObject:
        link->client->Call<object::StatusResponse>(
            service + ".Status", object::StatusRequest(), options.call_timeout,
            [finish, hash_refusal](net::Result<object::StatusResponse> r) {
              if (!r.ok()) return finish(false, "no status: " + r.status.ToString());
              if (auto why = hash_refusal(r.value.calibration_sha256()); !why.empty()) {
                return finish(false, why);
              }
              finish(true, "");
            });
        return;
      case Peer::kSound:
        link->client->Call<sound::ListBankResponse>(
            service + ".ListBank", sound::ListBankRequest(), options.call_timeout,
            [this, finish](net::Result<sound::ListBankResponse> r) {
              if (!r.ok()) return finish(false, "no sound bank: " + r.status.ToString());
              bank = std::move(r.value);
              finish(true, "");
            });
        return;
      default:
        finish(true, "");
    }
  }

  // A peer just reported up: its streams, and the voice daemon's news filter.
  void AfterUp(Link& link) {
    const Peer peer = link.peer;
    if (peer == Peer::kVoice) {
      // The newest sequence before (re)subscribing: what the daemon heard before is old news.
      link.client->Call<devices::LinkStatus>(
          Service(peer) + ".Status", devices::GetStatusRequest(), options.call_timeout,
          [this](net::Result<devices::LinkStatus> r) {
            Handle(VoiceSubscribed{r.ok() ? r.value.readings() : 0, NowNs()});
            Subscribe(*LinkOf(Peer::kVoice));
          });
      return;
    }
    Subscribe(link);
  }

  // Once per peer: the client subscribes again by itself after a reconnection.
  void Subscribe(Link& link) {
    if (link.subscribed) return;
    const std::string method = Service(link.peer) + ".Live";
    auto lost = [peer = link.peer](const net::Status& s) {
      spdlog::warn("{}'s live stream: {}", PeerName(peer), s.ToString());
    };
    switch (link.peer) {
      case Peer::kViewer:
        link.client->Subscribe<devices::ViewerState>(
            method, devices::SubscribeRequest(),
            [this](const devices::ViewerState& s) {
              Handle(ViewerReading{s, NowNs()});
            },
            lost);
        break;
      case Peer::kJoystick:
        link.client->Subscribe<devices::JoystickState>(
            method, devices::SubscribeRequest(),
            [this](const devices::JoystickState& s) {
              view.joystick_stamp_ns = s.stamp().receive_monotonic_ns();
              Handle(JoystickReading{s, NowNs()});
            },
            lost);
        break;
      case Peer::kPlatform:
        link.client->Subscribe<devices::PlatformState>(
            method, devices::SubscribeRequest(),
            [this](const devices::PlatformState& s) {
              Handle(PlatformReading{s, NowNs()});
            },
            lost);
        break;
      case Peer::kVoice:
        link.client->Subscribe<devices::VoiceState>(
            method, devices::SubscribeRequest(),
            [this](const devices::VoiceState& s) {
              Handle(VoiceReading{s, NowNs()});
            },
            lost);
        break;
      default:
        return;  // no stream the session follows
    }
    link.subscribed = true;
  }

  // ---- timers ----

  void Tick() {
    if (shutting_down) return;
    Handle(TickEvent{NowNs()});
    tick_timer.expires_after(options.tick);
    tick_timer.async_wait([weak = weak_from_this()](const boost::system::error_code& ec) {
      if (auto self = weak.lock(); self && !ec) self->Tick();
    });
  }

  // 1 Hz: each daemon's serial link, and every peer not up yet that is connected.
  void Health() {
    if (shutting_down) return;
    for (auto& [peer, link] : links) {
      if (!link.client->connected()) continue;
      if (!link.up) {
        CheckAndReport(link);
        continue;
      }
      if (!IsDaemon(peer)) continue;
      link.client->Call<devices::LinkStatus>(
          Service(peer) + ".Status", devices::GetStatusRequest(), options.call_timeout,
          [this, peer = peer](net::Result<devices::LinkStatus> r) {
            if (!r.ok()) return;  // a lost connection is reported by the client
            Link* link = LinkOf(peer);
            if (r.value.state() == link->link_state) return;
            link->link_state = r.value.state();
            Handle(DeviceLinkEvent{peer, r.value.state(), r.value.message(), NowNs()});
          });
    }
    health_timer.expires_after(options.health_period);
    health_timer.async_wait([weak = weak_from_this()](const boost::system::error_code& ec) {
      if (auto self = weak.lock(); self && !ec) self->Health();
    });
  }

  void Shutdown() {
    shutting_down = true;
    tick_timer.cancel();
    health_timer.cancel();
    for (auto& [peer, link] : links) link.client->Stop();
    work.reset();
  }
};

int64_t ControlApp::NowNs() { return MonotonicNs(); }

Result<std::unique_ptr<ControlApp>> ControlApp::Make(
    ControlAppOptions options, const calibration::StereoCalibration& calibration,
    std::unique_ptr<GeometricDatabase> database) {
  std::string error;
  if (!options.Check(&error)) return ErrorMessage{error};
  auto session = Session::Make(options.session, calibration, &error);
  if (!session) return ErrorMessage{error};
  auto impl = std::make_shared<Impl>();
  impl->options = std::move(options);
  impl->database = std::move(database);
  impl->session = std::move(session);
  return std::unique_ptr<ControlApp>(new ControlApp(std::move(impl)));
}

ControlApp::ControlApp(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}

ControlApp::~ControlApp() {
  Stop();
  if (impl_->thread.joinable()) {
    asio::post(impl_->io, [impl = impl_] { impl->Shutdown(); });
    // Closing every connection and ending the timers ends io.run(). Should anything still
    // hold it (a defect), the client must not hang on its way out: the loop is stopped after
    // a grace period, which leaves nothing unsaved (every model is committed before the
    // session hears of it). tests/control/app checks the grace is not needed.
    auto ended = impl_->loop_ended.get_future();
    if (ended.wait_for(std::chrono::seconds(3)) != std::future_status::ready) {
      spdlog::warn("control client: the network loop did not end by itself; stopping it");
      impl_->io.stop();
    }
    impl_->thread.join();
  }
}

void ControlApp::Start() {
  impl_->work.emplace(impl_->io.get_executor());
  impl_->Publish();
  asio::post(impl_->io, [impl = impl_] { impl->Connect(); });
  impl_->thread = std::thread([impl = impl_] {
    // An exception here is a defect; say what it was rather than leave a hung client.
    try {
      impl->io.run();
    } catch (const std::exception& e) {
      spdlog::critical("control client: {}", e.what());
      impl->Finish(1);
    }
    impl->loop_ended.set_value();
  });
}

int ControlApp::Wait() {
  std::unique_lock lock(impl_->exit_mutex);
  impl_->exited.wait(lock, [&] { return impl_->exit_code.has_value(); });
  return *impl_->exit_code;
}

void ControlApp::Stop(int exit_code) {
  asio::post(impl_->io, [impl = impl_, exit_code] { impl->Finish(exit_code); });
  if (!impl_->thread.joinable()) impl_->Finish(exit_code);
}

void ControlApp::Post(const Command& command) {
  asio::post(impl_->io, [impl = impl_, command] {
    if (impl->started) impl->Handle(CommandEvent{command, NowNs()});
  });
}

void ControlApp::Post(const PointerDrive& drive) {
  asio::post(impl_->io, [impl = impl_, drive] {
    if (impl->started) impl->Handle(PointerDriveEvent{drive, NowNs()});
  });
}

const ViewBoard& ControlApp::board() const { return impl_->board; }

}  // namespace igms::control
