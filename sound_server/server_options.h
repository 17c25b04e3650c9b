// The sound server's settings: its section of the lab configuration (processes.NAME.*)
// with command-line flags over it.
//
//   bank            the manifest.yaml of the bank (default: ../share/igms/sounds/manifest.yaml
//                   next to the executable, which is where the build and the install put it)
//   output          default | null | wave            (flag --output)
//   device          an OpenAL device name for "default"
//   wave_file       where the wave output writes     (flag --wave-file)
//   wave_rate       Hz of the null and wave outputs (default 22050)
//   period_frames   mixing period of the null and wave outputs (default 256)
//   fallback        none | null | wave: used when the default device cannot be opened
//   cue_sources     sources for cues (default 4)
//   speech_queue    messages that may wait (default 16)
//   volume          master volume 0..1 (default 1)
// Paths in the configuration file are relative to its folder; `output: null` and
// `fallback: null` (a YAML null) mean the null output.
#pragma once

#include <boost/program_options.hpp>
#include <filesystem>
#include <string>

#include "common/config/lab_ports.h"
#include "common/config/process_options.h"
#include "sound_server/audio_output.h"
#include "sound_server/engine.h"

namespace igms::sound {

inline constexpr std::uint16_t kDefaultPort = config::ports::kSound;

struct ServerSettings {
  std::filesystem::path manifest;
  OutputOptions output;
  EngineOptions engine;
};

// The component's own flags, for ParseProcessOptions.
boost::program_options::options_description SoundFlags();
// The keys above, and max_frame_bytes (net::ServerKeys), for ParseProcessOptions.
config::Keys SoundKeys();

// Reads the settings; `executable` anchors the default bank. Throws config::ConfigError
// for a key of the wrong type, and returns an error message for a value out of range.
std::string ReadSettings(const config::ProcessOptions& process,
                         const std::filesystem::path& executable, ServerSettings& settings);

}  // namespace igms::sound
