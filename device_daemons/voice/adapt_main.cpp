// igms-voice-adapt: enrolment. Adapts the recogniser's acoustic model to a speaker from
// their speech and what they said (adaptation.h), and writes a model folder for
// `igms-voiced --model-dir` and `igms-voice-decode --model-dir`.
//
//   igms-voice-adapt --out DIR --record [--device NAME]   read the prompts aloud, one by one
//   igms-voice-adapt --out DIR --list FILE                 recordings: "FILE<TAB>what was said"
//   igms-voice-adapt --out DIR --espeak VOICE:WPM ...      espeak-ng says the prompts
//   igms-voice-adapt --print-prompts                       the prompts, one a line
// --prompts FILE (one a line) replaces the built-in prompts for --record and --espeak.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <boost/program_options.hpp>
#include <chrono>
#include <csignal>
#include <fstream>
#include <iostream>
#include <thread>

#include "common/config/exit_codes.h"
#include "common/version/version.h"
#include "device_daemons/voice/adaptation.h"
#include "device_daemons/voice/endpointer.h"
#include "device_daemons/voice/evaluation.h"
#include "device_daemons/voice/microphone.h"

namespace po = boost::program_options;
using namespace igms::voice;

namespace {

volatile std::sig_atomic_t g_stop = 0;

// "path<TAB>transcript" lines; blank lines and '#' comments skipped.
std::optional<std::vector<AdaptationUtterance>> ReadList(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    spdlog::error("cannot read {}", path);
    return std::nullopt;
  }
  std::vector<AdaptationUtterance> out;
  int line_number = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    if (line.empty() || line[0] == '#') continue;
    const size_t tab = line.find('\t');
    if (tab == std::string::npos) {
      spdlog::error("{}:{}: expected a sound file, a tab and what was said", path, line_number);
      return std::nullopt;
    }
    auto audio = LoadSoundFile(line.substr(0, tab));
    if (!audio.ok()) {
      spdlog::error("{}:{}: {}", path, line_number, audio.error());
      return std::nullopt;
    }
    out.push_back({std::move(*audio), line.substr(tab + 1)});
  }
  return out;
}

// Prompts each sentence and keeps the first utterance heard after it (up to 15 s each).
std::optional<std::vector<AdaptationUtterance>> Record(const std::string& device,
                                                       const std::vector<std::string>& prompts) {
  std::string error;
  auto mic = Microphone::Open(device, &error);
  if (!mic) {
    spdlog::error("{}", error);
    return std::nullopt;
  }
  std::vector<AdaptationUtterance> out;
  // A prompt is asked again until something is heard after it.
  while (out.size() < prompts.size() && !g_stop) {
    const size_t i = out.size();
    std::cout << "[" << i + 1 << "/" << prompts.size() << "] say: " << prompts[i] << std::endl;
    // A prompt is a sentence, not a command: up to 12 s of it is one utterance; longer is
    // dropped (the endpointer's rule) and the prompt asked again.
    EndpointerOptions sentence;
    sentence.max_utterance_s = 12.0;
    Endpointer endpointer(sentence);
    std::vector<int16_t> samples;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(15);
    std::optional<std::vector<int16_t>> heard;
    while (!heard && !g_stop && std::chrono::steady_clock::now() < deadline) {
      samples.clear();
      if (!mic->Read(samples)) {
        spdlog::error("the capture device stopped");
        return std::nullopt;
      }
      for (auto& utterance : endpointer.Feed(samples)) heard = std::move(utterance);
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (heard) {
      out.push_back({Audio{std::move(*heard)}, prompts[i]});
    } else if (!g_stop) {
      std::cout << "  nothing heard; again" << std::endl;
    }
  }
  if (g_stop) return std::nullopt;
  return out;
}

std::optional<std::vector<AdaptationUtterance>> Espeak(const std::vector<std::string>& specs,
                                                       const std::vector<std::string>& prompts) {
  std::vector<Voice> voices;
  for (const std::string& spec : specs) {
    const size_t colon = spec.rfind(':');
    Voice voice{spec.substr(0, colon), 175};
    if (colon != std::string::npos) {
      try {
        voice.words_per_minute = std::stoi(spec.substr(colon + 1));
      } catch (const std::exception&) {
        spdlog::error("bad --espeak '{}': expected VOICE:WORDS_PER_MINUTE", spec);
        return std::nullopt;
      }
    }
    voices.push_back(voice);
  }
  auto out = SynthesizeEnrolment(voices, prompts);
  if (!out.ok()) {
    spdlog::error("{}", out.error());
    return std::nullopt;
  }
  return std::move(*out);
}

}  // namespace

int main(int argc, char** argv) try {
  spdlog::set_default_logger(spdlog::stderr_color_mt("igms-voice-adapt"));
  AdaptationOptions options;
  std::string list, device, prompts_file;
  std::vector<std::string> espeak;
  po::options_description desc("igms-voice-adapt: adapt the recogniser to a speaker");
  desc.add_options()("help,h", "this help")("version", "print the version and exit")(
      "out", po::value(&options.out_dir), "folder for the adapted model (replaced)")(
      "model-dir", po::value(&options.model_dir)->default_value(options.model_dir),
      "the pocketsphinx model to adapt")("record", "read the prompts aloud into the microphone")(
      "device", po::value(&device), "capture device for --record (default: the system's)")(
      "list", po::value(&list), "recordings: lines of 'sound file<TAB>what was said'")(
      "espeak", po::value(&espeak)->multitoken(), "espeak-ng voices VOICE:WPM say the prompts")(
      "sphinxtrain-dir",
      po::value(&options.sphinxtrain_dir)->default_value(options.sphinxtrain_dir),
      "where sphinxtrain's bw and map_adapt are")("keep-work", po::value(&options.work_dir),
                                                  "keep features, counts and logs here")(
      "prompts", po::value(&prompts_file), "prompts to read, one a line, instead of the built-in")(
      "print-prompts", "print the enrolment prompts and exit");
  po::variables_map vm;
  po::store(po::parse_command_line(argc, argv, desc), vm);
  po::notify(vm);
  if (vm.count("help")) {
    std::cout << desc << "\n";
    return igms::kExitOk;
  }
  if (vm.count("version")) {
    std::cout << igms::version::Line("igms-voice-adapt") << "\n";
    return 0;
  }
  std::vector<std::string> prompts = EnrolmentPrompts();
  if (!prompts_file.empty()) {
    std::ifstream in(prompts_file);
    prompts.clear();
    for (std::string line; std::getline(in, line);) {
      if (line.find_first_not_of(" \t") != std::string::npos) prompts.push_back(line);
    }
    if (prompts.empty()) {
      spdlog::error("no prompts in {}", prompts_file);
      return igms::kExitUsage;
    }
  }
  if (vm.count("print-prompts")) {
    for (const std::string& p : prompts) std::cout << p << "\n";
    return igms::kExitOk;
  }
  const int sources = int(vm.count("record")) + int(!list.empty()) + int(!espeak.empty());
  if (sources != 1) {
    spdlog::error("give exactly one of --record, --list FILE, --espeak VOICE:WPM...");
    return igms::kExitUsage;
  }
  std::string error;
  if (!options.Check(&error)) {
    spdlog::error("{}", error);
    return igms::kExitUsage;
  }
  std::signal(SIGINT, [](int) { g_stop = 1; });
  std::signal(SIGTERM, [](int) { g_stop = 1; });
  const auto utterances = !list.empty()     ? ReadList(list)
                          : !espeak.empty() ? Espeak(espeak, prompts)
                                            : Record(device, prompts);
  if (!utterances) return igms::kExitFailure;
  const AdaptationReport report = AdaptModel(*utterances, options);
  if (!report.ok()) {
    spdlog::error("{}", report.error);
    return igms::kExitFailure;
  }
  spdlog::info("adapted to {} utterances ({:.0f} s of speech): {}", report.utterances,
               report.seconds, options.out_dir);
  return igms::kExitOk;
} catch (const std::exception& e) {
  spdlog::error("{}", e.what());
  return igms::kExitUsage;
}
