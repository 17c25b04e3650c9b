#include "sound_server/engine.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "sound_server/audio_file.h"

namespace igms::sound {

struct Engine::Sound {
  SoundEntry entry;
  ALuint buffer = 0;  // 0 when the file could not be loaded
  std::string error;
  double seconds = 0.0;
  int sample_rate = 0;
};

struct Engine::Voice {
  ALuint source = 0;
  uint64_t play_id = 0;  // 0: free
  const Sound* sound = nullptr;
  PlayPriority priority = PlayPriority::kNormal;
  float volume = 1.0f;
};

struct Engine::Pending {
  uint64_t play_id = 0;
  const Sound* sound = nullptr;
  PlayPriority priority = PlayPriority::kNormal;
  float volume = 1.0f;
};

namespace {

bool ValidPriority(PlayPriority p) { return p >= PlayPriority::kLow && p <= PlayPriority::kHigh; }

bool ValidVolume(float v) { return std::isfinite(v) && v >= 0.0f && v <= 1.0f; }

std::string Describe(const SoundEntry& entry) {
  return "sound " + std::to_string(entry.id) + " '" + entry.key + "'";
}

}  // namespace

const char* PriorityName(PlayPriority priority) {
  switch (priority) {
    case PlayPriority::kLow:
      return "low";
    case PlayPriority::kNormal:
      return "normal";
    case PlayPriority::kHigh:
      return "high";
  }
  return "?";
}

bool EngineOptions::Check(std::string* error) const {
  if (cue_sources < 1 || cue_sources > 64) {
    *error = "cue sources must be 1-64";
    return false;
  }
  if (speech_queue_limit < 1 || speech_queue_limit > 1000) {
    *error = "speech queue must be 1-1000";
    return false;
  }
  if (!ValidVolume(master_volume)) {
    *error = "master volume must be 0-1";
    return false;
  }
  if (poll_period.count() < 1 || poll_period.count() > 100) {
    *error = "poll period must be 1-100 ms";
    return false;
  }
  return true;
}

EngineResult Engine::Create(Manifest manifest, std::unique_ptr<AudioOutput> output,
                            const EngineOptions& options) {
  EngineResult result;
  if (std::string error; !options.Check(&error)) {
    result.error = "sound engine: " + error;
    return result;
  }
  if (!output) {
    result.error = "sound engine: no audio output";
    return result;
  }
  std::unique_ptr<Engine> engine(new Engine());
  engine->manifest_ = std::move(manifest);
  engine->options_ = options;
  engine->output_ = std::move(output);
  alGetError();
  for (const SoundEntry& entry : engine->manifest_.sounds) {
    auto sound = std::make_unique<Sound>();
    sound->entry = entry;
    Result<AudioClip> file = ReadAudioFile(engine->manifest_.FileOf(entry));
    if (file.ok()) {
      const AudioClip& clip = *file;
      alGenBuffers(1, &sound->buffer);
      alBufferData(sound->buffer, AL_FORMAT_MONO16, clip.samples.data(),
                   static_cast<ALsizei>(clip.samples.size() * sizeof(int16_t)), clip.sample_rate);
      if (alGetError() != AL_NO_ERROR) {
        if (sound->buffer != 0) alDeleteBuffers(1, &sound->buffer);
        sound->buffer = 0;
        sound->error = "OpenAL refused its audio";
      }
      sound->seconds = clip.Seconds();
      sound->sample_rate = clip.sample_rate;
    } else {
      sound->error = file.error();
    }
    if (!sound->error.empty()) {
      result.warnings.push_back(Describe(entry) + " cannot be played: " + sound->error);
    }
    engine->sounds_.push_back(std::move(sound));
  }
  std::vector<ALuint> sources(options.cue_sources + 1);
  alGenSources(static_cast<ALsizei>(sources.size()), sources.data());
  if (alGetError() != AL_NO_ERROR) {
    result.error =
        "sound engine: OpenAL cannot make " + std::to_string(sources.size()) + " sources";
    return result;
  }
  engine->cues_.resize(options.cue_sources);
  engine->speech_ = std::make_unique<Voice>();
  for (size_t i = 0; i < sources.size(); ++i) {
    Voice& voice = i < engine->cues_.size() ? engine->cues_[i] : *engine->speech_;
    voice.source = sources[i];
    // Every sound is heard as recorded: no position, no distance attenuation.
    alSourcei(voice.source, AL_SOURCE_RELATIVE, AL_TRUE);
    alSource3f(voice.source, AL_POSITION, 0.0f, 0.0f, 0.0f);
    alSourcef(voice.source, AL_ROLLOFF_FACTOR, 0.0f);
  }
  engine->master_volume_ = options.master_volume;
  alListenerf(AL_GAIN, options.master_volume);
  engine->poller_ = std::thread([e = engine.get()] { e->PollLoop(); });
  result.engine = std::move(engine);
  return result;
}

Engine::~Engine() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (poller_.joinable()) poller_.join();
  if (output_) {
    for (Voice& voice : cues_) {
      alSourceStop(voice.source);
      alDeleteSources(1, &voice.source);
    }
    if (speech_) {
      alSourceStop(speech_->source);
      alDeleteSources(1, &speech_->source);
    }
    for (auto& sound : sounds_) {
      if (sound->buffer != 0) alDeleteBuffers(1, &sound->buffer);
    }
  }
}

const Engine::Sound* Engine::Resolve(const SoundRef& ref, Outcome& outcome) const {
  const SoundEntry* entry = ref.id != 0 ? manifest_.FindId(ref.id) : manifest_.FindKey(ref.key);
  if (entry == nullptr) {
    if (ref.id == 0 && ref.key.empty()) {
      outcome = Outcome::Error(Failure::kBadRequest, "name a sound: give an id or a key");
    } else {
      outcome =
          Outcome::Error(Failure::kNotFound,
                         (ref.id != 0 ? "no sound with id " + std::to_string(ref.id)
                                      : "no sound with key '" + ref.key + "'") +
                             " in the bank " + manifest_.path.string() + " (ListBank lists them)");
    }
    return nullptr;
  }
  const Sound& sound = *sounds_[entry - manifest_.sounds.data()];
  if (sound.buffer == 0) {
    outcome = Outcome::Error(Failure::kUnavailable,
                             Describe(sound.entry) + " cannot be played: " + sound.error);
    return nullptr;
  }
  return &sound;
}

PlayOutcome Engine::Play(const PlayParams& params) {
  std::lock_guard lock(mutex_);
  PlayOutcome result;
  if (!ValidPriority(params.priority)) {
    result.outcome = Outcome::Error(Failure::kBadRequest, "priority must be low, normal or high");
  } else if (!ValidVolume(params.volume)) {
    result.outcome = Outcome::Error(Failure::kBadRequest, "volume must be between 0 and 1, got " +
                                                              std::to_string(params.volume));
  } else if (const Sound* sound = Resolve(params.sound, result.outcome); sound != nullptr) {
    if (!output_->connected()) {
      result.outcome = Outcome::Error(Failure::kUnavailable,
                                      "the audio device '" + output_->device_name() + "' is lost");
    } else {
      Reap();
      result = sound->entry.kind == SoundKind::kCue ? PlayCue(*sound, params)
                                                    : PlaySpeech(*sound, params);
      result.entry = &sound->entry;
      result.seconds = sound->seconds;
    }
  }
  if (!result.outcome.ok()) ++plays_refused_;
  return result;
}

PlayOutcome Engine::PlayCue(const Sound& sound, const PlayParams& params) {
  PlayOutcome result;
  Voice* chosen = nullptr;
  for (Voice& voice : cues_) {
    if (voice.play_id == 0) {
      chosen = &voice;
      break;
    }
  }
  if (chosen == nullptr) {
    for (Voice& voice : cues_) {
      if (voice.priority > params.priority) continue;
      if (chosen == nullptr || voice.priority < chosen->priority ||
          (voice.priority == chosen->priority && voice.play_id < chosen->play_id)) {
        chosen = &voice;
      }
    }
  }
  if (chosen == nullptr) {
    result.outcome = Outcome::Error(Failure::kUnavailable,
                                    "all " + std::to_string(cues_.size()) +
                                        " cue sources are playing sounds of higher priority");
    return result;
  }
  StopVoice(*chosen);
  result.play_id = next_play_id_++;
  StartVoice(*chosen, sound, result.play_id, params.priority, params.volume);
  return result;
}

PlayOutcome Engine::PlaySpeech(const Sound& sound, const PlayParams& params) {
  PlayOutcome result;
  Voice& voice = *speech_;
  const bool idle = voice.play_id == 0 && queue_.empty();
  if (idle || (voice.play_id != 0 && params.priority > voice.priority)) {
    StopVoice(voice);
    result.play_id = next_play_id_++;
    StartVoice(voice, sound, result.play_id, params.priority, params.volume);
    return result;
  }
  if (queue_.size() >= options_.speech_queue_limit) {
    result.outcome = Outcome::Error(
        Failure::kUnavailable,
        "the speech queue is full (" + std::to_string(queue_.size()) + " messages waiting)");
    return result;
  }
  auto at = std::find_if(queue_.begin(), queue_.end(),
                         [&](const Pending& p) { return p.priority < params.priority; });
  result.play_id = next_play_id_++;
  at = queue_.insert(at, Pending{result.play_id, &sound, params.priority, params.volume});
  result.queued = true;
  result.queue_position = static_cast<size_t>(at - queue_.begin()) + 1;
  return result;
}

void Engine::StartVoice(Voice& voice, const Sound& sound, uint64_t play_id, PlayPriority priority,
                        float volume) {
  if (&voice == speech_.get() && priority == PlayPriority::kHigh) {
    for (Voice& cue : cues_) {
      if (cue.play_id != 0 && cue.priority < priority) StopVoice(cue);
    }
  }
  voice.play_id = play_id;
  voice.sound = &sound;
  voice.priority = priority;
  voice.volume = volume;
  alSourcei(voice.source, AL_BUFFER, static_cast<ALint>(sound.buffer));
  alSourcef(voice.source, AL_GAIN, volume);
  alSourcePlay(voice.source);
  ++plays_started_;
}

void Engine::StopVoice(Voice& voice) {
  if (voice.play_id == 0) return;
  alSourceStop(voice.source);
  alSourcei(voice.source, AL_BUFFER, 0);
  voice.play_id = 0;
  voice.sound = nullptr;
}

void Engine::Reap() {
  for (Voice& voice : cues_) {
    ALint state = AL_STOPPED;
    if (voice.play_id != 0) alGetSourcei(voice.source, AL_SOURCE_STATE, &state);
    if (state != AL_PLAYING) StopVoice(voice);
  }
  ALint state = AL_STOPPED;
  if (speech_->play_id != 0) alGetSourcei(speech_->source, AL_SOURCE_STATE, &state);
  if (state == AL_PLAYING) return;
  StopVoice(*speech_);
  if (!queue_.empty()) {
    const Pending next = queue_.front();
    queue_.pop_front();
    StartVoice(*speech_, *next.sound, next.play_id, next.priority, next.volume);
  }
}

void Engine::PollLoop() {
  std::unique_lock lock(mutex_);
  bool connected = true;
  while (!stopping_) {
    wake_.wait_for(lock, options_.poll_period);
    if (stopping_) break;
    Reap();
    if (connected && !output_->connected()) {
      connected = false;
      spdlog::error(
          "the audio device '{}' is lost: plays are refused until the server is "
          "restarted",
          output_->device_name());
    }
  }
}

Outcome Engine::Stop(uint64_t play_id, size_t* stopped) {
  std::lock_guard lock(mutex_);
  size_t count = 0;
  auto stop_voice = [&](Voice& voice) {
    if (voice.play_id != 0 && (play_id == 0 || voice.play_id == play_id)) {
      StopVoice(voice);
      ++count;
    }
  };
  for (Voice& voice : cues_) stop_voice(voice);
  stop_voice(*speech_);
  const size_t waiting = queue_.size();
  std::erase_if(queue_, [&](const Pending& p) { return play_id == 0 || p.play_id == play_id; });
  count += waiting - queue_.size();
  if (stopped != nullptr) *stopped = count;
  if (play_id != 0 && count == 0) {
    return Outcome::Error(Failure::kNotFound, "play " + std::to_string(play_id) +
                                                  " is neither playing nor queued (it may "
                                                  "have finished)");
  }
  return {};
}

Outcome Engine::SetMasterVolume(float volume) {
  if (!ValidVolume(volume)) {
    return Outcome::Error(Failure::kBadRequest,
                          "master volume must be between 0 and 1, got " + std::to_string(volume));
  }
  std::lock_guard lock(mutex_);
  master_volume_ = volume;
  alListenerf(AL_GAIN, volume);
  return {};
}

std::vector<BankSound> Engine::Bank() const {
  std::vector<BankSound> bank;
  for (const auto& sound : sounds_) {
    bank.push_back(
        {sound->entry, sound->buffer != 0, sound->error, sound->seconds, sound->sample_rate});
  }
  return bank;
}

EngineStatus Engine::Status() const {
  std::lock_guard lock(mutex_);
  EngineStatus status;
  status.output = output_->output();
  status.device_name = output_->device_name();
  status.sample_rate = output_->sample_rate();
  status.device_connected = output_->connected();
  status.master_volume = master_volume_;
  status.cue_sources = static_cast<int>(cues_.size());
  status.speech_queue_limit = options_.speech_queue_limit;
  status.plays_started = plays_started_;
  status.plays_refused = plays_refused_;
  auto add_voice = [&](const Voice& voice) {
    if (voice.play_id == 0) return;
    ALint state = AL_STOPPED;
    alGetSourcei(voice.source, AL_SOURCE_STATE, &state);
    if (state != AL_PLAYING) return;  // finished; the poll thread frees it shortly
    ALfloat position = 0.0f;
    alGetSourcef(voice.source, AL_SEC_OFFSET, &position);
    status.plays.push_back({voice.play_id, voice.sound->entry, voice.priority, voice.volume, true,
                            position, voice.sound->seconds});
  };
  for (const Voice& voice : cues_) add_voice(voice);
  add_voice(*speech_);
  for (const Pending& p : queue_) {
    status.plays.push_back(
        {p.play_id, p.sound->entry, p.priority, p.volume, false, 0.0, p.sound->seconds});
  }
  return status;
}

bool Engine::Idle() const { return Status().plays.empty(); }

}  // namespace igms::sound
