// What the session asks of the world (its effects): platform orientations, grabs, ranges,
// locates, sounds, the voice grammar's state, and the models stored in the database.
#include "control/app/control_app_impl.h"

namespace igms::control {

using app_detail::ToCallError;

void ControlApp::Impl::Execute(const SetOrientationEffect& e) {
  devices::SetOrientationRequest request;
  request.set_yaw_ticks(e.ticks.yaw);
  request.set_pitch_ticks(e.ticks.pitch);
  request.set_roll_ticks(e.ticks.roll);
  request.set_steps_per_move(e.steps_per_move);
  request.set_take_control(e.take_control);
  CallPeer<devices::SetOrientationResponse>(
      Peer::kPlatform, "SetOrientation", request, options.call_timeout,
      [this, call = e.call](const net::Result<devices::SetOrientationResponse>& r) {
        SetOrientationReply reply{call, std::nullopt, NowNs()};
        if (!r.ok()) reply.error = ToCallError(r.status);
        Handle(reply);
      });
}

void ControlApp::Impl::Execute(const GrabEffect& e) {
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

void ControlApp::Impl::Execute(const RangeEffect& e) {
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

void ControlApp::Impl::Execute(const LocateEffect& e) {
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

void ControlApp::Impl::Execute(const SetOperatorStateEffect& e) {
  if (!Up(Peer::kVoice)) return;
  devices::SetOperatorStateRequest request;
  request.set_state(e.state);
  CallPeer<devices::SetOperatorStateResponse>(
      Peer::kVoice, "SetOperatorState", request, options.call_timeout,
      [this, state = e.state](const net::Result<devices::SetOperatorStateResponse>& r) {
        if (!r.ok()) {
          Note(spdlog::level::warn, "voice grammar not set: " + r.status.ToString());
          return;
        }
        view.voice_grammar = state;
        Publish();
      });
}

void ControlApp::Impl::Play(const std::string& key, sound::Priority priority) {
  // A lost sound server never stops a session: while it is away nothing is played.
  if (!Up(Peer::kSound)) return;
  sound::PlayRequest request;
  request.set_key(key);
  request.set_priority(priority);
  CallPeer<sound::PlayResponse>(
      Peer::kSound, "Play", request, options.call_timeout,
      [this, key](const net::Result<sound::PlayResponse>& r) {
        // A session faster than speech (a script) keeps the sound server's queue full, and
        // a cue now and then gets in as one ends: warn once every 10 s at most, with the count
        // of cues refused meanwhile, not for every cue.
        if (r.ok()) return;
        const auto now = std::chrono::steady_clock::now();
        if (sound_warned != std::chrono::steady_clock::time_point{} &&
            now - sound_warned < std::chrono::seconds(10)) {
          ++sound_refusals;
          spdlog::debug("sound '{}' not played: {}", key, r.status.ToString());
          return;
        }
        spdlog::warn(
            "sound '{}' not played: {} ({}refusals in the next 10 s logged at debug level)", key,
            r.status.ToString(),
            sound_refusals > 0
                ? fmt::format("{} more refused since the last warning; ", sound_refusals)
                : std::string());
        sound_warned = now;
        sound_refusals = 0;
      });
}

void ControlApp::Impl::Execute(const PlaySoundEffect& e) { Play(e.key, e.priority); }

void ControlApp::Impl::Execute(const SpeakFailureEffect& e) {
  const std::string key = FailureMessageKey(bank, e.reason);
  if (key.empty()) {
    if (Up(Peer::kSound)) {
      spdlog::warn("the sound bank has no message for {}", object::FailureReason_Name(e.reason));
    }
    return;
  }
  Play(key, sound::PRIORITY_NORMAL);
}

std::vector<ServerVersion> ControlApp::Impl::Servers() {
  std::vector<ServerVersion> servers;
  for (auto& [peer, link] : links) {
    if (!link.version.program.empty()) servers.push_back(link.version);
  }
  return servers;
}

void ControlApp::Impl::Execute(const StoreModelEffect& e) {
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

void ControlApp::Impl::Execute(const RemoveModelEffect& e) {
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

void ControlApp::Impl::ModelsChanged() {
  if (!options.models_changed) return;
  auto present = database->ListModels();
  if (!present.ok()) return Note(spdlog::level::err, "the database: " + present.error());
  options.models_changed(std::move(*present));
}

void ControlApp::Impl::Execute(const RestoreModelEffect& e) {
  if (database) UndoInDatabase(e.id);
}

void ControlApp::Impl::UndoInDatabase(uint64_t session_id) {
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

// the view carries the display mode
void ControlApp::Impl::Execute(const DisplayEffect&) {}

void ControlApp::Impl::Execute(const NoticeEffect& e) {
  const auto level = e.level == NoticeLevel::kError     ? spdlog::level::err
                     : e.level == NoticeLevel::kWarning ? spdlog::level::warn
                                                        : spdlog::level::info;
  Note(level, e.text);
}

void ControlApp::Impl::Execute(const ExitEffect& e) {
  Note(spdlog::level::critical, e.message);
  Finish(e.code);
}

}  // namespace igms::control
