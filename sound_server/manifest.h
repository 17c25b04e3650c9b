// The sound bank's manifest: the one place a sound is defined.
//
// A manifest is a YAML file (sound_server/bank/manifest.yaml is the lab's) with top-level
// keys `format` (1), `sample_rate` (Hz of the generated audio), `peak_db`, `voice`, `speed`
// (espeak-ng's voice and words per minute) and a list `sounds`. Each sound has:
//   id       a positive number, unique in the bank (the thesis's "number id", section 2.2.1)
//   key      a unique name of lower-case letters, digits and '_' ("camera_click")
//   kind     `cue` (a short sound that may sound over anything) or `speech` (a spoken
//            message; messages are queued so they never talk over each other)
//   file     the audio file, relative to the manifest's folder; defaults to
//            cues/<key>.wav or speech/<key>.wav
//   text     speech only, required: the sentence spoken
//   sox      cue only, required: the sox effects that synthesise it from silence
//   channels cue only, optional (default 1): channels the sox effects synthesise, mixed down
//   meaning  optional: what the sound tells the operator (Cooke, tables 2.5 and 2.6)
//   reason   optional: the object server's failure reason this message speaks, by its exact
//            enum value name in igms/object.proto ("FAILURE_MARKS_DEGENERATE")
//
// LoadManifest never throws on bad input: a missing file, bad YAML, a missing or mistyped
// field, a duplicate id or key all come back as an error message naming the file and the
// entry, so the server can refuse to start with a clear reason.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/base/result.h"

namespace igms::sound {

enum class SoundKind { kCue, kSpeech };

// "cue" or "speech".
const char* KindName(SoundKind kind);

struct SoundEntry {
  uint32_t id = 0;
  std::string key;
  SoundKind kind = SoundKind::kCue;
  std::string file;  // relative to the manifest's folder
  std::string text;  // speech: the sentence
  std::string sox;   // cue: sox effects
  int channels = 1;  // cue: channels sox synthesises before the mix-down
  std::string meaning;
  std::string reason;
};

struct Manifest {
  std::filesystem::path path;  // the manifest file itself
  int sample_rate = 22050;
  double peak_db = -3.0;
  std::string voice = "en-us";
  int speed = 160;
  std::vector<SoundEntry> sounds;

  // The folder the entries' files are relative to.
  std::filesystem::path Folder() const { return path.parent_path(); }
  // An entry's audio file as a full path.
  std::filesystem::path FileOf(const SoundEntry& entry) const { return Folder() / entry.file; }
  // Looks an entry up; nullptr when there is none.
  const SoundEntry* FindId(uint32_t id) const;
  const SoundEntry* FindKey(const std::string& key) const;
};

// Parses a manifest file: the manifest, or what is wrong and where. See the file comment for
// the format and the checks made.
Result<Manifest> LoadManifest(const std::filesystem::path& path);

// Parses manifest text; `path` only names the file in messages and anchors relative files.
Result<Manifest> ParseManifest(const std::string& text, const std::filesystem::path& path);

}  // namespace igms::sound
