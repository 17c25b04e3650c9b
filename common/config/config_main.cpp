// igms config: reads the lab configuration for scripts (the launcher, systemd, compose).
//   igms config get KEY [--config FILE]      prints the value (a scalar, or YAML)
//   igms config processes [--config FILE]    prints each process's name
//   igms config dump [--config FILE]         prints the whole file as IGMS reads it
//   igms config check [--config FILE]        exits 0 if the file loads
// FILE defaults to $IGMS_CONFIG. Exit status: 0 found, 1 key missing, 2 bad input.
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "common/config/lab_config.h"
#include "common/version/version.h"

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  std::string file = std::getenv("IGMS_CONFIG") ? std::getenv("IGMS_CONFIG") : "";
  std::vector<std::string> positional;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--config" && i + 1 < args.size()) {
      file = args[++i];
    } else if (args[i] == "-h" || args[i] == "--help") {
      std::cout << "usage: igms config get KEY | processes | dump | check  [--config FILE]\n"
                   "       igms config --version\n";
      return 0;
    } else if (args[i] == "--version") {
      std::cout << igms::version::Line("igms-config") << "\n";
      return 0;
    } else {
      positional.push_back(args[i]);
    }
  }
  if (positional.empty()) {
    std::cerr << "igms config: say what to do: get KEY, processes, dump or check\n";
    return 2;
  }
  if (file.empty()) {
    std::cerr << "igms config: no configuration file (use --config FILE or set IGMS_CONFIG)\n";
    return 2;
  }
  try {
    const auto config = igms::config::LabConfig::Load(file);
    const std::string& verb = positional[0];
    if (verb == "get" && positional.size() == 2) {
      const YAML::Node node = config.Find(positional[1]);
      if (!node.IsDefined() || node.IsNull()) {
        std::cerr << "igms config: " << file << ": no key " << positional[1] << "\n";
        return 1;
      }
      if (node.IsScalar()) {
        std::cout << node.Scalar() << "\n";
      } else {
        YAML::Emitter out;
        out << node;
        std::cout << out.c_str() << "\n";
      }
      return 0;
    }
    if (verb == "processes") {
      for (const auto& name : config.ProcessNames()) std::cout << name << "\n";
      return 0;
    }
    if (verb == "dump") {
      std::cout << config.Dump() << "\n";
      return 0;
    }
    if (verb == "check") return 0;
    std::cerr << "igms config: unknown command (get KEY, processes, dump, check)\n";
    return 2;
  } catch (const igms::config::ConfigError& e) {
    std::cerr << "igms config: " << e.what() << "\n";
    return 2;
  }
}
