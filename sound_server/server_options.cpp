#include "sound_server/server_options.h"

#include "common/net/process_server.h"

namespace igms::sound {

namespace po = boost::program_options;

po::options_description SoundFlags() {
  po::options_description flags("Sound server options (each also processes.NAME.<key>)");
  flags.add_options()("bank", po::value<std::string>(), "the bank's manifest.yaml")(
      "output", po::value<std::string>(), "default, null or wave")(
      "device", po::value<std::string>(), "OpenAL device name for the default output")(
      "wave-file", po::value<std::string>(), "where the wave output writes")(
      "wave-rate", po::value<int>(), "Hz of the null and wave outputs")(
      "period-frames", po::value<int>(), "mixing period of the null and wave outputs")(
      "fallback", po::value<std::string>(), "none, null or wave: when no device opens")(
      "cue-sources", po::value<int>(), "sources for cues")(
      "speech-queue", po::value<int>(), "messages that may wait")("volume", po::value<float>(),
                                                                  "master volume 0..1");
  return flags;
}

config::Keys SoundKeys(ServerSettings* s) {
  using config::KeyType;
  config::Keys keys = net::ServerKeys();
  keys.BindPath("bank", &s->bank,
                "the bank's manifest.yaml (default: share/igms/sounds beside the program)", "bank");
  keys.BindChoice("output", &s->output.output, {"default", "null", "wave"}, "where the sound goes",
                  "output");
  keys.Bind("device", &s->output.device, "OpenAL device name for the default output", "device");
  keys.BindPath("wave_file", &s->output.wave_file, "where the wave output writes", "wave-file",
                KeyType::kOutputPath);
  keys.Bind("wave_rate", &s->output.wave_rate, "Hz of the null and wave outputs", "wave-rate");
  keys.Bind("period_frames", &s->output.period_frames, "mixing period of the null and wave outputs",
            "period-frames");
  keys.BindChoice("fallback", &s->output.fallback, {"none", "null", "wave"},
                  "used when the default device cannot be opened", "fallback");
  keys.Bind("cue_sources", &s->engine.cue_sources, "sources for cues", "cue-sources");
  keys.Bind("speech_queue", &s->speech_queue, "messages that may wait", "speech-queue");
  keys.Bind("volume", &s->engine.master_volume, "master volume 0..1", "volume");
  return keys;
}

namespace {

// `output: null` and `fallback: null` in YAML are a null value, not the word (so the bound
// field keeps its default): read them as the null output, which is what a person writing
// them means.
void NullIsAWord(const config::ProcessOptions& p, const char* flag, const char* key,
                 std::string* mode) {
  if (p.flags.count(flag)) return;
  const YAML::Node node = p.config.Find(p.Key(key));
  if (node.IsDefined() && node.IsNull()) *mode = "null";
}

}  // namespace

std::string ReadSettings(const config::ProcessOptions& p, const std::filesystem::path& executable,
                         ServerSettings& s) {
  const std::filesystem::path default_bank =
      executable.parent_path() / ".." / "share" / "igms" / "sounds" / "manifest.yaml";
  s.manifest = s.bank.empty() ? default_bank.lexically_normal() : std::filesystem::path(s.bank);
  NullIsAWord(p, "output", "output", &s.output.output);
  NullIsAWord(p, "fallback", "fallback", &s.output.fallback);
  if (s.speech_queue < 1) return "the speech queue must hold at least 1 message";
  s.engine.speech_queue_limit = static_cast<size_t>(s.speech_queue);
  std::string error;
  if (!s.output.Check(&error) || !s.engine.Check(&error)) return error;
  return "";
}

}  // namespace igms::sound
