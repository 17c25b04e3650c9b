// The session's peers: connecting to each, checking what it serves (thesis 2.4's start-up
// checks), reporting it up or down, and subscribing to its streams.
#include "control/app/control_app_impl.h"

namespace igms::control {

using app_detail::kPing;
using app_detail::LinkGood;
using app_detail::Service;
using std::chrono::milliseconds;

void ControlApp::Impl::Connect() {
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
        // Captured by name, not as the structured binding (which clang before 16 refuses).
        [weak = weak_from_this(), peer = link.peer](net::ConnectionState state,
                                                    const std::string& why) {
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

void ControlApp::Impl::StartSession() {
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

void ControlApp::Impl::OnConnection(Peer peer, net::ConnectionState state, const std::string& why) {
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

void ControlApp::Impl::CheckAndReport(Link& link) {
  if (link.checking || link.up) return;
  Check(link, [this, peer = link.peer](const PeerReport& report) {
    Link* link = LinkOf(peer);
    if (!link || link->up || !report.up || !started) return;
    link->up = true;
    AfterUp(*link);
    Handle(PeerUpEvent{peer, NowNs()});
  });
}

void ControlApp::Impl::Check(Link& link, std::function<void(PeerReport)> done) {
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
      [this, peer, finish](const net::Result<PingResponse>& r) {
        if (!r.ok()) return finish(false, "no answer to a ping: " + r.status.ToString());
        Link* link = LinkOf(peer);
        link->version = {link->address.name, r.value.program(), r.value.version()};
        CheckService(peer, finish);
      });
}

void ControlApp::Impl::CheckService(Peer peer,
                                    const std::function<void(bool, std::string)>& finish) {
  Link* link = LinkOf(peer);
  const std::string service = Service(peer);
  auto hash_refusal = [this](const std::string& theirs) -> std::string {
    if (theirs.empty() || options.calibration_hash.empty() || theirs == options.calibration_hash) {
      return "";
    }
    return "its calibration (sha256 " + theirs.substr(0, 12) + "...) differs from ours (" +
           options.calibration_hash.substr(0, 12) + "...)";
  };
  if (IsDaemon(peer)) {
    link->client->Call<devices::LinkStatus>(
        service + ".Status", devices::GetStatusRequest(), options.call_timeout,
        [this, peer, finish](const net::Result<devices::LinkStatus>& r) {
          if (!r.ok()) return finish(false, "no status: " + r.status.ToString());
          LinkOf(peer)->link_state = r.value.state();
          if (!LinkGood(r.value.state())) {
            return finish(false, "its serial link is " + devices::LinkState_Name(r.value.state()) +
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
          [this, finish, hash_refusal](const net::Result<video::StatusResponse>& r) {
            if (!r.ok()) return finish(false, "no status: " + r.status.ToString());
            if (auto why = hash_refusal(r.value.calibration_sha256()); !why.empty()) {
              return finish(false, why);
            }
            LinkOf(Peer::kVideo)
                ->client->Call<video::GetOverlayResponse>(
                    Service(Peer::kVideo) + ".GetOverlay", video::GetOverlayRequest(),
                    options.call_timeout,
                    [this, finish](const net::Result<video::GetOverlayResponse>& o) {
                      if (!o.ok()) return finish(false, "no overlay: " + o.status.ToString());
                      overlay = o.value.settings();
                      finish(true, "");
                    });
          });
      return;
    case Peer::kObject:
      link->client->Call<object::StatusResponse>(
          service + ".Status", object::StatusRequest(), options.call_timeout,
          [finish, hash_refusal](const net::Result<object::StatusResponse>& r) {
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

void ControlApp::Impl::AfterUp(Link& link) {
  const Peer peer = link.peer;
  if (peer == Peer::kVoice) {
    // The newest sequence before (re)subscribing: what the daemon heard before is old news.
    link.client->Call<devices::LinkStatus>(
        Service(peer) + ".Status", devices::GetStatusRequest(), options.call_timeout,
        [this](const net::Result<devices::LinkStatus>& r) {
          Handle(VoiceSubscribed{r.ok() ? r.value.readings() : 0, NowNs()});
          Subscribe(*LinkOf(Peer::kVoice));
        });
    return;
  }
  Subscribe(link);
}

void ControlApp::Impl::Subscribe(Link& link) {
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

}  // namespace igms::control
