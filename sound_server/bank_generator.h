// Generates a sound bank's audio from its manifest, with no recorded or downloaded audio:
// cues are synthesised by sox from the entry's `sox` effects, spoken messages by espeak-ng
// from the entry's `text`. Every file comes out as 16-bit mono WAV at the manifest's
// sample rate, normalised to its `peak_db`. See manifest.h for the manifest format.
//
// The build runs this (through `igms-sound-bank`) into <build>/share/igms/sounds, which is
// installed to <prefix>/share/igms/sounds: the manifest is copied next to the audio, so the
// folder is a complete bank the server can load.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "sound_server/manifest.h"

namespace igms::sound {

struct GenerateOptions {
  std::string sox = "sox";  // programs, looked up on PATH
  std::string espeak = "espeak-ng";
  bool verbose = false;
};

struct GenerateResult {
  int generated = 0;
  std::vector<std::string> errors;  // one per entry that failed, naming the entry and command
  bool ok() const { return errors.empty(); }
};

// Writes every entry's file under `out_dir` (folders created) and copies the manifest to
// `out_dir`/manifest.yaml. A failing entry is reported and the others still generated.
GenerateResult GenerateBank(const Manifest& manifest, const std::filesystem::path& out_dir,
                            const GenerateOptions& options = {});

}  // namespace igms::sound
