// igms-voiced: the voice daemon (docs/voice.md, docs/devices.md, docs/protocol-devices.md).
//   --serial PORT --baud 9600 | --simulate | --replay FILE    a Dragon speech PC, its
//                                                             simulator, or a recording
//   --microphone [--device NAME] | --wav FILE...              the recogniser instead
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>

#include "common/config/exit_codes.h"
#include "common/config/lab_ports.h"
#include "common/config/process_options.h"
#include "common/net/process_server.h"
#include "device_daemons/voice/adaptation.h"
#include "device_daemons/voice/voice_daemon.h"

int main(int argc, char** argv) {
  namespace po = boost::program_options;
  using namespace igms;
  po::options_description flags("Voice");
  devices::AddDaemonFlags(&flags);
  flags.add_options()("microphone", po::bool_switch(),
                      "recognise speech from a microphone (OpenAL capture)")(
      "device", po::value<std::string>(),
      "capture device for --microphone (default: the system's)")(
      "wav", po::value<std::vector<std::string>>()->multitoken(),
      "recognise these sound files, one a --wav-interval-ms")(
      "wav-interval-ms", po::value<int>(), "time between the sound files (default 1000)")(
      "state", po::value<std::string>(),
      "initial operator state: verification, model_building, awaiting_type")(
      "min-confidence", po::value<double>(),
      "recogniser: reject commands below this confidence (0..1; default 0.2, 0.01 with an "
      "adapted model)")("model-dir", po::value<std::string>(),
                        "recogniser: pocketsphinx en-us model folder");
  voice::VoiceConfig config;
  devices::DaemonConfig daemon;
  int exit_code = 0;
  const auto process = config::ParseProcessOptions(
      argc, argv, "voice", "The voice daemon: spoken commands as two-digit codes over TCP.", flags,
      voice::VoiceKeys(&config, &daemon), &exit_code);
  if (!process) return exit_code;
  try {
    const auto& f = process->flags;
    voice::VoiceDaemonOptions voice;
    const auto initial = voice::StateFromName(config.state);
    if (!initial) {
      spdlog::error("unknown state '{}' (verification, model_building, awaiting_type)",
                    config.state);
      return kExitUsage;
    }
    voice.initial_state = *initial;
    const bool microphone = config.microphone;
    const auto wav =
        f.count("wav") ? f["wav"].as<std::vector<std::string>>() : std::vector<std::string>();
    devices::DaemonOptions options;
    std::string error;
    if (microphone || !wav.empty()) {
      if (f.count("serial") || f["simulate"].as<bool>() || f.count("replay") ||
          (microphone && !wav.empty())) {
        spdlog::error("name only one of --serial, --simulate, --replay, --microphone and --wav");
        return kExitUsage;
      }
      voice::SpeechListenerOptions listen;
      listen.microphone = microphone;
      listen.device = config.device;
      listen.files = wav;
      listen.file_interval = std::chrono::milliseconds(
          f.count("wav-interval-ms") ? f["wav-interval-ms"].as<int>() : 1000);
      // An operator's adapted model (igms-voice-adapt) is named here or in the lab file, and
      // brings the settings chosen for enrolled operators (adaptation.h).
      listen.recognizer = voice::RecognizerOptionsFor(config.model_dir);
      if (voice::IsAdaptedModel(listen.recognizer.model_dir)) {
        spdlog::info(
            "adapted model {}: {} decoys per command, min_confidence {}, {} common words at {}",
            listen.recognizer.model_dir, listen.recognizer.decoys.max_per_command,
            listen.recognizer.min_confidence, listen.recognizer.fillers.count,
            listen.recognizer.fillers.weight);
      }
      if (f.count("min-confidence"))
        listen.recognizer.min_confidence = f["min-confidence"].as<double>();
      if (!listen.Check(&error)) {
        spdlog::error("{}", error);
        return kExitUsage;
      }
      voice.listen = listen;
      options.source = devices::SourceKind::kSerial;  // the recogniser stands in for the line
      options.record_file = daemon.record;
    } else if (!devices::ReadDaemonOptions(*process, daemon, "voice", &options, &error)) {
      spdlog::error("{} (or --microphone, --wav FILE...)", error);
      return kExitUsage;
    }
    if (process->check_only) return config::CheckPassed(*process);
    boost::asio::io_context io;
    voice::VoiceDaemon daemon(io, options,
                              net::ServerOptionsFor(*process, igms::config::ports::kVoice), voice);
    return devices::RunDaemonProcess(
        io,
        [&](std::string* e) {
          if (!daemon.Start(e)) return false;
          spdlog::info("voice daemon on port {}", daemon.port());
          return true;
        },
        [&] { daemon.Stop(); });
  } catch (const config::ConfigError& e) {
    spdlog::error("{}", e.what());
    return kExitUsage;
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return kExitFailure;
  }
}
