// The sound server's playback engine: the bank in OpenAL buffers, a few sources, a speech
// queue, priorities, volume and stop (Cooke, section 2.2.1: "when the sound server receives
// an identification number it plays the corresponding sound").
//
// Sources. `cue_sources` sources play cues, any number at once, mixed; one more source
// speaks. So a cue always sounds over speech, and two messages never talk over each other.
//
// Priorities (low < normal < high; "high" is for prompts that need an answer):
//  - A cue takes a free cue source. When all are busy it takes the one playing the cue of
//    lowest priority not above its own (the oldest of those), cutting that cue off; when
//    every busy source plays something more important, the request is refused.
//  - A message starts at once when nothing is being said. Otherwise, if it is more
//    important than the message being said, it cuts that message off and starts;
//    else it waits in the queue behind every waiting message of at least its priority.
//    A full queue (`speech_queue_limit`) refuses the request.
//  - A high-priority message, when it starts, cuts off the cues of lower priority, so a
//    prompt is heard clearly.
//
// Volume. Each play has a volume in [0, 1] (a linear gain on the sound as generated); the
// master volume in [0, 1] scales everything. A mono sound at volume 1 reaches the output
// at its recorded level.
//
// Errors. Unknown ids and keys, sounds whose file was missing or corrupt at start-up,
// a volume out of range, a full queue or a lost device are refused with a message; the
// engine never throws on a request. All methods are thread-safe. A poll thread (every
// `poll_period`) frees finished sources and starts the next message of the queue, and
// logs once when OpenAL reports the device gone (OpenAL Soft 1.19 cannot reopen a device:
// plays are refused until the server restarts).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "sound_server/audio_output.h"
#include "sound_server/manifest.h"

namespace igms::sound {

enum class PlayPriority { kLow = 1, kNormal = 2, kHigh = 3 };
const char* PriorityName(PlayPriority priority);

struct EngineOptions {
  int cue_sources = 4;
  size_t speech_queue_limit = 16;
  float master_volume = 1.0f;
  std::chrono::milliseconds poll_period{5};
  bool Check(std::string* error) const;  // false, with *error, when invalid
};

enum class Failure { kNone, kBadRequest, kNotFound, kUnavailable };

struct Outcome {
  Failure failure = Failure::kNone;
  std::string message;
  bool ok() const { return failure == Failure::kNone; }
  static Outcome Error(Failure failure, std::string message) {
    return {failure, std::move(message)};
  }
};

// Names a sound of the bank: by id when `id` is not 0, else by key.
struct SoundRef {
  uint32_t id = 0;
  std::string key;
};

struct PlayParams {
  SoundRef sound;
  PlayPriority priority = PlayPriority::kNormal;
  float volume = 1.0f;
};

struct PlayOutcome {
  Outcome outcome;
  uint64_t play_id = 0;       // names this play in Stop and Status; ids start at 1
  bool queued = false;        // speech waiting behind another message
  size_t queue_position = 0;  // when queued: 1 = next to be said
  const SoundEntry* entry = nullptr;
  double seconds = 0.0;  // length of the sound
};

// A sound of the bank as loaded.
struct BankSound {
  SoundEntry entry;
  bool available = false;  // false: its file was missing or corrupt; `error` says which
  std::string error;
  double seconds = 0.0;
  int sample_rate = 0;
};

struct PlayState {
  uint64_t play_id = 0;
  SoundEntry entry;
  PlayPriority priority = PlayPriority::kNormal;
  float volume = 1.0f;
  bool playing = false;   // false: waiting in the speech queue
  double position = 0.0;  // seconds played so far
  double seconds = 0.0;   // length
};

struct EngineStatus {
  std::string output;       // "default", "null" or "wave"
  std::string device_name;  // OpenAL's name of the device
  int sample_rate = 0;
  bool device_connected = true;
  float master_volume = 1.0f;
  int cue_sources = 0;
  size_t speech_queue_limit = 0;
  std::vector<PlayState> plays;  // playing first (cues, then speech), then the queue in order
  uint64_t plays_started = 0;
  uint64_t plays_refused = 0;
};

class Engine;
struct EngineResult {
  std::unique_ptr<Engine> engine;
  std::string error;                  // when engine is empty
  std::vector<std::string> warnings;  // sounds that could not be loaded, one line each
};

class Engine {
 public:
  // Loads every sound of the manifest (a sound that fails to load is recorded and refused
  // when asked for, not fatal), creates the sources and starts the poll thread.
  static EngineResult Create(Manifest manifest, std::unique_ptr<AudioOutput> output,
                             const EngineOptions& options = {});
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  PlayOutcome Play(const PlayParams& params);
  // Stops one play (playing or queued), or with play_id 0 everything and the queue.
  // `stopped` receives how many plays ended. Unknown play id: kNotFound.
  Outcome Stop(uint64_t play_id, size_t* stopped = nullptr);
  Outcome SetMasterVolume(float volume);
  std::vector<BankSound> Bank() const;
  EngineStatus Status() const;
  // True when nothing plays and nothing waits.
  bool Idle() const;
  const Manifest& manifest() const { return manifest_; }

 private:
  struct Sound;
  struct Voice;
  struct Pending;
  Engine() = default;
  const Sound* Resolve(const SoundRef& ref, Outcome& outcome) const;
  PlayOutcome PlayCue(const Sound& sound, const PlayParams& params);
  PlayOutcome PlaySpeech(const Sound& sound, const PlayParams& params);
  void StartVoice(Voice& voice, const Sound& sound, uint64_t play_id, PlayPriority priority,
                  float volume);
  void StopVoice(Voice& voice);
  void Reap();
  void PollLoop();

  Manifest manifest_;
  EngineOptions options_;
  std::unique_ptr<AudioOutput> output_;
  std::vector<std::unique_ptr<Sound>> sounds_;
  std::vector<Voice> cues_;
  std::unique_ptr<Voice> speech_;
  std::deque<Pending> queue_;
  float master_volume_ = 1.0f;
  uint64_t next_play_id_ = 1;
  uint64_t plays_started_ = 0;
  uint64_t plays_refused_ = 0;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread poller_;
};

}  // namespace igms::sound
