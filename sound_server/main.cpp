// igms-sound-server: plays the lab's sounds and spoken messages (Cooke, section 2.2.1).
//   igms-sound-server --config lab.yaml --name sound
//   igms-sound-server --port 7303 --output wave --wave-file out.wav
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>
#include <filesystem>

#include "common/config/exit_codes.h"
#include "common/config/process_options.h"
#include "common/net/process_server.h"
#include "common/net/server.h"
#include "sound_server/server_options.h"
#include "sound_server/sound_service.h"

namespace sound = igms::sound;

int Run(int argc, char** argv) {
  int exit_code = 0;
  sound::ServerSettings settings;
  auto process = igms::config::ParseProcessOptions(
      argc, argv, "sound", "igms-sound-server: plays the lab's sounds and spoken messages",
      sound::SoundFlags(), sound::SoundKeys(&settings), &exit_code);
  if (!process) return exit_code;
  if (std::string error =
          sound::ReadSettings(*process, std::filesystem::canonical("/proc/self/exe"), settings);
      !error.empty()) {
    spdlog::error("{}", error);
    return igms::kExitUsage;
  }
  igms::Result<sound::Manifest> manifest = sound::LoadManifest(settings.manifest);
  if (!manifest.ok()) {
    spdlog::error("{}", manifest.error());
    return igms::kExitUsage;
  }
  if (process->check_only) return igms::config::CheckPassed(*process);
  sound::OutputResult output = sound::OpenOutput(settings.output);
  if (!output.warning.empty()) spdlog::warn("{}", output.warning);
  if (!output.output) {
    spdlog::error("{}", output.error);
    return igms::kExitUnavailable;
  }
  spdlog::info("playing on the {} output '{}' at {} Hz", output.output->output(),
               output.output->device_name(), output.output->sample_rate());
  sound::EngineResult engine =
      sound::Engine::Create(std::move(*manifest), std::move(output.output), settings.engine);
  for (const std::string& warning : engine.warnings) spdlog::warn("{}", warning);
  if (!engine.engine) {
    spdlog::error("{}", engine.error);
    return igms::kExitUnavailable;
  }
  spdlog::info("sound bank {}: {} sounds, {} playable", settings.manifest.string(),
               engine.engine->Bank().size(), engine.engine->Bank().size() - engine.warnings.size());

  boost::asio::io_context io;
  igms::net::Server server(io, igms::net::ServerOptionsFor(*process, sound::kDefaultPort));
  sound::RegisterSoundService(server, *engine.engine);
  server.Start();
  const auto signals = igms::net::StopOnSignal(io, [&] {
    server.Stop();
    io.stop();
  });
  io.run();
  engine.engine->Stop(0);
  return igms::kExitOk;
}

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const igms::config::ConfigError& e) {
    spdlog::error("igms-sound-server: {}", e.what());
    return igms::kExitUsage;
  } catch (const std::exception& e) {
    spdlog::error("igms-sound-server: {}", e.what());
    return igms::kExitFailure;
  }
}
