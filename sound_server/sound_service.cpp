#include "sound_server/sound_service.h"

#include <spdlog/spdlog.h>

#include <cmath>

#include "igms/sound.pb.h"

namespace igms::sound {
namespace {

net::Status ToStatus(const Outcome& outcome) {
  switch (outcome.failure) {
    case Failure::kNone:
      return net::Status::Ok();
    case Failure::kBadRequest:
      return net::Status::Error(igms::BAD_REQUEST, outcome.message);
    case Failure::kNotFound:
      return net::Status::Error(igms::NOT_FOUND, outcome.message);
    case Failure::kUnavailable:
      return net::Status::Error(igms::UNAVAILABLE, outcome.message);
  }
  return net::Status::Error(igms::INTERNAL, outcome.message);
}

Kind ToKind(SoundKind kind) { return kind == SoundKind::kCue ? CUE : SPEECH; }

uint32_t Millis(double seconds) { return static_cast<uint32_t>(std::lround(seconds * 1000.0)); }

net::Status Play(Engine& engine, const PlayRequest& req, PlayResponse& resp) {
  PlayParams params;
  switch (req.sound_case()) {
    case PlayRequest::kId:
      if (req.id() == 0) return net::Status::Error(igms::BAD_REQUEST, "sound id 0 names nothing");
      params.sound.id = req.id();
      break;
    case PlayRequest::kKey:
      if (req.key().empty()) return net::Status::Error(igms::BAD_REQUEST, "empty sound key");
      params.sound.key = req.key();
      break;
    default:
      return net::Status::Error(igms::BAD_REQUEST,
                                "name a sound: set 'id' or 'key' (ListBank lists them)");
  }
  if (req.priority() == PRIORITY_UNSPECIFIED) {
    params.priority = PlayPriority::kNormal;
  } else if (req.priority() >= PRIORITY_LOW && req.priority() <= PRIORITY_HIGH) {
    params.priority = static_cast<PlayPriority>(req.priority());
  } else {
    return net::Status::Error(igms::BAD_REQUEST,
                              "unknown priority " + std::to_string(req.priority()));
  }
  params.volume = req.has_volume() ? req.volume() : 1.0f;
  const PlayOutcome played = engine.Play(params);
  if (!played.outcome.ok()) {
    spdlog::debug("play refused: {}", played.outcome.message);
    return ToStatus(played.outcome);
  }
  resp.set_play_id(played.play_id);
  resp.set_queued(played.queued);
  resp.set_queue_position(static_cast<uint32_t>(played.queue_position));
  resp.set_id(played.entry->id);
  resp.set_key(played.entry->key);
  resp.set_kind(ToKind(played.entry->kind));
  resp.set_duration_ms(Millis(played.seconds));
  return net::Status::Ok();
}

void FillStatus(const EngineStatus& s, StatusResponse& resp) {
  resp.set_output(s.output);
  resp.set_device(s.device_name);
  resp.set_device_connected(s.device_connected);
  resp.set_sample_rate(static_cast<uint32_t>(s.sample_rate));
  resp.set_master_volume(s.master_volume);
  resp.set_cue_sources(static_cast<uint32_t>(s.cue_sources));
  resp.set_speech_queue_limit(static_cast<uint32_t>(s.speech_queue_limit));
  resp.set_plays_started(s.plays_started);
  resp.set_plays_refused(s.plays_refused);
  for (const PlayState& p : s.plays) {
    PlayInfo* info = resp.add_plays();
    info->set_play_id(p.play_id);
    info->set_id(p.entry.id);
    info->set_key(p.entry.key);
    info->set_kind(ToKind(p.entry.kind));
    info->set_priority(static_cast<Priority>(p.priority));
    info->set_volume(p.volume);
    info->set_playing(p.playing);
    info->set_position_ms(Millis(p.position));
    info->set_duration_ms(Millis(p.seconds));
  }
}

}  // namespace

void RegisterSoundService(net::Server& server, Engine& engine) {
  server.Handle<PlayRequest, PlayResponse>(
      kPlayMethod,
      [&engine](const PlayRequest& req, PlayResponse& resp) { return Play(engine, req, resp); });
  server.Handle<StopRequest, StopResponse>(
      kStopMethod, [&engine](const StopRequest& req, StopResponse& resp) {
        size_t stopped = 0;
        const Outcome outcome = engine.Stop(req.play_id(), &stopped);
        resp.set_stopped(static_cast<uint32_t>(stopped));
        return ToStatus(outcome);
      });
  server.Handle<ListBankRequest, ListBankResponse>(
      kListBankMethod, [&engine](const ListBankRequest&, ListBankResponse& resp) {
        resp.set_manifest(engine.manifest().path.string());
        for (const BankSound& s : engine.Bank()) {
          BankEntry* e = resp.add_sounds();
          e->set_id(s.entry.id);
          e->set_key(s.entry.key);
          e->set_kind(ToKind(s.entry.kind));
          e->set_text(s.entry.text);
          e->set_meaning(s.entry.meaning);
          e->set_reason(s.entry.reason);
          e->set_available(s.available);
          e->set_error(s.error);
          e->set_duration_ms(Millis(s.seconds));
        }
        return net::Status::Ok();
      });
  server.Handle<StatusRequest, StatusResponse>(
      kStatusMethod, [&engine](const StatusRequest&, StatusResponse& resp) {
        FillStatus(engine.Status(), resp);
        return net::Status::Ok();
      });
  server.Handle<SetVolumeRequest, SetVolumeResponse>(
      kSetVolumeMethod, [&engine](const SetVolumeRequest& req, SetVolumeResponse& resp) {
        const Outcome outcome = engine.SetMasterVolume(req.master_volume());
        resp.set_master_volume(engine.Status().master_volume);
        return ToStatus(outcome);
      });
}

}  // namespace igms::sound
