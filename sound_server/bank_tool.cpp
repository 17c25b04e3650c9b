// igms-sound-bank: generates the sound bank's audio from its manifest (see bank_generator.h).
//   igms-sound-bank --manifest sound_server/bank/manifest.yaml --out build/share/igms/sounds
#include <spdlog/spdlog.h>

#include <boost/program_options.hpp>
#include <fstream>
#include <iostream>

#include "common/config/exit_codes.h"
#include "common/version/version.h"
#include "sound_server/bank_generator.h"

namespace po = boost::program_options;

int main(int argc, char** argv) {
  try {
    std::string manifest_path, out_dir, stamp;
    igms::sound::GenerateOptions options;
    po::options_description flags("igms-sound-bank: generate the sound bank from its manifest");
    flags.add_options()("help,h", "this help")("version", "print the version and exit")(
        "manifest", po::value(&manifest_path)->required(), "the bank's manifest.yaml")(
        "out", po::value(&out_dir)->required(), "folder to write the bank into")(
        "stamp", po::value(&stamp), "file touched when every sound was generated")(
        "sox", po::value(&options.sox)->default_value("sox"), "the sox program")(
        "espeak", po::value(&options.espeak)->default_value("espeak-ng"), "the espeak-ng program");
    po::variables_map vm;
    po::store(po::parse_command_line(argc, argv, flags), vm);
    if (vm.count("help")) {
      std::cout << flags << "\n";
      return igms::kExitOk;
    }
    if (vm.count("version")) {
      std::cout << igms::version::Line("igms-sound-bank") << "\n";
      return 0;
    }
    po::notify(vm);
    const igms::Result<igms::sound::Manifest> loaded = igms::sound::LoadManifest(manifest_path);
    if (!loaded.ok()) {
      spdlog::error("{}", loaded.error());
      return igms::kExitUsage;
    }
    const igms::sound::GenerateResult result = igms::sound::GenerateBank(*loaded, out_dir, options);
    for (const std::string& error : result.errors) spdlog::error("{}", error);
    if (!result.ok()) return igms::kExitFailure;
    spdlog::info("generated {} sounds into {}", result.generated, out_dir);
    if (!stamp.empty()) std::ofstream(stamp) << result.generated << "\n";
    return igms::kExitOk;
  } catch (const std::exception& e) {
    spdlog::error("igms-sound-bank: {}", e.what());
    return igms::kExitUsage;
  }
}
