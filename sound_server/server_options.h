// The sound server's settings: its section of the lab configuration (processes.NAME.*)
// with command-line flags over it. The keys, their types, defaults and flags are declared
// once, in SoundKeys (`igms-sound-server --help` lists them). Paths in the configuration
// file are relative to its folder; `output: null` and `fallback: null` (a YAML null) mean
// the null output.
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
  std::string bank;  // the bank key (made absolute) or flag; empty: the installed bank
  std::filesystem::path manifest;
  OutputOptions output;
  EngineOptions engine;
  int speech_queue = 16;  // engine.speech_queue_limit once checked (at least 1)
};

// The component's own flags, for ParseProcessOptions.
boost::program_options::options_description SoundFlags();
// The keys, and max_frame_bytes (net::ServerKeys), for ParseProcessOptions, which fills the
// fields of `settings` they bind (flags over the file; paths resolved beside the lab file).
config::Keys SoundKeys(ServerSettings* settings);

// The rest of the settings, after ParseProcessOptions: the manifest (`executable` anchors
// the default bank), a YAML null output or fallback taken as the null output, then the
// checks. Returns "" or what is out of range.
std::string ReadSettings(const config::ProcessOptions& process,
                         const std::filesystem::path& executable, ServerSettings& settings);

}  // namespace igms::sound
