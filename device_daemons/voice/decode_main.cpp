// igms-voice-decode: the voice recogniser as a command-line tool (the daemon that serves
// the network is igms-voiced). Prints the two-digit code of every accepted command on
// stdout, one per line, as the Dragon Writer's PC sent them (Cooke, section 2.1.6);
// rejections and details go to the log on stderr.
//
//   igms-voice-decode [options] ITEM...     ITEM is a sound file, or state=NAME to switch the
//                                     grammar for the files after it (the control
//                                     client's word on the system's state)
//   igms-voice-decode --mic [--device NAME] listen until interrupted
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <boost/program_options.hpp>
#include <chrono>
#include <csignal>
#include <iostream>
#include <thread>

#include "common/config/exit_codes.h"
#include "common/version/version.h"
#include "device_daemons/voice/adaptation.h"
#include "device_daemons/voice/audio.h"
#include "device_daemons/voice/endpointer.h"
#include "device_daemons/voice/microphone.h"
#include "device_daemons/voice/recognizer.h"

namespace po = boost::program_options;
using namespace igms::voice;

namespace {

volatile std::sig_atomic_t g_stop = 0;

void Report(const Recognition& r, bool verbose) {
  if (r.accepted) {
    std::cout << Code(*r.command);
    if (verbose) std::cout << " " << Phrase(*r.command) << " " << r.confidence;
    std::cout << std::endl;
    spdlog::info("accepted \"{}\" (code {}, confidence {:.2f}, {:.1f} ms)", Phrase(*r.command),
                 Code(*r.command), r.confidence, r.decode_ms);
  } else {
    spdlog::warn("rejected in state {}: {} ({:.1f} ms)", StateName(r.state), r.message,
                 r.decode_ms);
  }
}

int RunFiles(Recognizer& recognizer, const std::vector<std::string>& items, bool verbose) {
  int failures = 0;
  for (const std::string& item : items) {
    if (item.starts_with("state=")) {
      const auto state = StateFromName(item.substr(6));
      if (!state) {
        spdlog::error("unknown state '{}' (verification, model_building, awaiting_type)",
                      item.substr(6));
        return igms::kExitUsage;
      }
      recognizer.SetState(*state);
      continue;
    }
    const auto audio = LoadSoundFile(item);
    if (!audio.ok()) {
      spdlog::error("{}", audio.error());
      ++failures;
      continue;
    }
    Report(recognizer.Recognize(audio->samples), verbose);
  }
  return failures ? 1 : 0;
}

int RunMicrophone(Recognizer& recognizer, const std::string& device, bool verbose) {
  std::string error;
  auto mic = Microphone::Open(device, &error);
  if (!mic) {
    spdlog::error("{}", error);
    return igms::kExitFailure;
  }
  Endpointer endpointer;
  std::vector<int16_t> samples;
  spdlog::info("listening in state {}", StateName(recognizer.state()));
  while (!g_stop) {
    samples.clear();
    if (!mic->Read(samples)) {
      spdlog::error("the capture device stopped");
      return igms::kExitFailure;
    }
    for (const auto& utterance : endpointer.Feed(samples)) {
      Report(recognizer.Recognize(utterance), verbose);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return igms::kExitOk;
}

}  // namespace

int main(int argc, char** argv) try {
  // stdout carries the codes alone; the log goes to stderr.
  spdlog::set_default_logger(spdlog::stderr_color_mt("igms-voice-decode"));
  RecognizerOptions options;
  double min_confidence = options.min_confidence;
  int decoys = 0;
  int fillers = 0;
  double filler_weight = 1.0;
  std::string state = "verification", device;
  std::vector<std::string> items;
  po::options_description desc("igms-voice-decode: spoken commands to two-digit codes");
  desc.add_options()("help,h", "this help")("version", "print the version and exit")(
      "state", po::value(&state)->default_value(state),
      "initial state: verification, model_building, awaiting_type")(
      "model-dir", po::value(&options.model_dir)->default_value(options.model_dir),
      "pocketsphinx en-us model folder")(
      "min-confidence", po::value(&min_confidence),
      "reject commands below this confidence (0..1; default 0.2, 0.01 with an adapted model)")(
      "decoys", po::value(&decoys),
      "near words per command that compete with it (default 0, 15 with an adapted model)")(
      "fillers", po::value(&fillers),
      "check each command against this many common English words (default 0)")(
      "filler-weight", po::value(&filler_weight),
      "a common word's weight relative to a command's (default 1)")(
      "no-predict", "keep the state until told (no prediction after own commands)")(
      "mic", "listen to a microphone (OpenAL capture) instead of files")(
      "device", po::value(&device), "capture device name (default: the system's)")(
      "list-devices", "print the capture devices and exit")(
      "verbose,v", "print phrase and confidence after each code")(
      "item", po::value(&items), "sound files and state=NAME switches");
  po::positional_options_description positional;
  positional.add("item", -1);
  po::variables_map vm;
  po::store(po::command_line_parser(argc, argv).options(desc).positional(positional).run(), vm);
  po::notify(vm);
  if (vm.count("help")) {
    std::cout << desc << "\n";
    return igms::kExitOk;
  }
  if (vm.count("version")) {
    std::cout << igms::version::Line("igms-voice-decode") << "\n";
    return 0;
  }
  if (vm.count("list-devices")) {
    for (const auto& name : Microphone::DeviceNames()) std::cout << name << "\n";
    return igms::kExitOk;
  }
  const auto initial = StateFromName(state);
  if (!initial) {
    spdlog::error("unknown state '{}'", state);
    return igms::kExitUsage;
  }
  // An adapted model (igms-voice-adapt) brings the settings chosen for enrolled operators.
  const std::string model_dir = options.model_dir;
  options = RecognizerOptionsFor(model_dir);
  if (vm.count("min-confidence")) options.min_confidence = min_confidence;
  if (vm.count("decoys")) options.decoys.max_per_command = decoys;
  if (vm.count("fillers")) options.fillers.count = fillers;
  if (vm.count("filler-weight")) options.fillers.weight = filler_weight;
  if (IsAdaptedModel(model_dir)) {
    spdlog::info(
        "adapted model {}: {} decoys per command, min_confidence {}, {} common words at {}",
        model_dir, options.decoys.max_per_command, options.min_confidence, options.fillers.count,
        options.fillers.weight);
  }
  options.initial_state = *initial;
  options.predict_state = !vm.count("no-predict");
  if (!vm.count("mic") && items.empty()) {
    spdlog::error("give sound files, or --mic");
    return igms::kExitUsage;
  }
  std::string error;
  auto recognizer = Recognizer::Create(options, &error);
  if (!recognizer) {
    spdlog::error("{}", error);
    return igms::kExitUsage;
  }
  std::signal(SIGINT, [](int) { g_stop = 1; });
  std::signal(SIGTERM, [](int) { g_stop = 1; });
  const bool verbose = vm.count("verbose") > 0;
  return vm.count("mic") ? RunMicrophone(*recognizer, device, verbose)
                         : RunFiles(*recognizer, items, verbose);
} catch (const std::exception& e) {
  spdlog::error("{}", e.what());
  return igms::kExitUsage;
}
