#include "common/config/process_options.h"

#include <spdlog/spdlog.h>

#include <malloc.h>

#include <iostream>

#include "common/log/log.h"
#include "common/version/version.h"

namespace igms::config {

namespace po = boost::program_options;

std::uint16_t ProcessOptions::Port(std::uint16_t fallback) const {
  const int port = Get<int>("port", fallback);
  if (port < 0 || port > 65535) {
    throw config.Error(Key("port"), config.Find(Key("port")), "must be a port number (0-65535)");
  }
  return static_cast<std::uint16_t>(port);
}

std::string ProcessOptions::HostOf(const std::string& process) const {
  return config.Get<std::string>("processes." + process + ".host", "127.0.0.1");
}

std::uint16_t ProcessOptions::PortOf(const std::string& process) const {
  const std::string key = "processes." + process + ".port";
  const int port = config.Get<int>(key);
  if (port <= 0 || port > 65535) throw config.Error(key, config.Find(key), "must be 1-65535");
  return static_cast<std::uint16_t>(port);
}

void TuneAllocator() {
  // Frames of images and large requests are allocated and freed many times a second; above
  // glibc's default mmap threshold each one is a fresh mapping whose pages fault in on every
  // copy. Keeping them on the heap more than halved the time of a 500 KB request.
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
}

std::optional<ProcessOptions> ParseProcessOptions(int argc, char** argv,
                                                  const std::string& default_name,
                                                  const std::string& summary,
                                                  const po::options_description& extra,
                                                  int* exit_code) {
  po::options_description common("Lab options");
  common.add_options()("help,h", "show this help")("version", "print the version and exit")(
      "config", po::value<std::string>(), "the lab configuration file (YAML)")(
      "name", po::value<std::string>()->default_value(default_name),
      "this process's entry under 'processes' in the configuration")(
      "set", po::value<std::vector<std::string>>()->composing(),
      "override a configuration key: --set processes.video.port=7400")(
      "host", po::value<std::string>(), "shorthand for processes.NAME.host")(
      "port", po::value<int>(), "shorthand for processes.NAME.port (0: any free port)")(
      "bind", po::value<std::string>(), "shorthand for processes.NAME.bind (listen address)")(
      "log-level", po::value<std::string>(), "trace, debug, info, warn, error (default info)");
  po::options_description all;
  all.add(common).add(extra);

  ProcessOptions out;
  try {
    po::store(po::parse_command_line(argc, argv, all), out.flags);
    po::notify(out.flags);
  } catch (const po::error& e) {
    std::cerr << argv[0] << ": " << e.what() << " (see --help)\n";
    *exit_code = 2;
    return std::nullopt;
  }
  if (out.flags.count("help")) {
    std::cout << summary << "\n\n" << all << "\n";
    *exit_code = 0;
    return std::nullopt;
  }
  if (out.flags.count("version")) {
    std::cout << version::Line(version::ProgramName()) << "\n";
    *exit_code = 0;
    return std::nullopt;
  }
  out.name = out.flags["name"].as<std::string>();
  try {
    if (out.flags.count("config")) out.config = LabConfig::Load(out.flags["config"].as<std::string>());
    if (out.flags.count("set")) {
      for (const auto& kv : out.flags["set"].as<std::vector<std::string>>()) {
        const auto eq = kv.find('=');
        if (eq == std::string::npos || eq == 0) {
          throw ConfigError("--set expects KEY=VALUE, got '" + kv + "'");
        }
        out.config.Set(kv.substr(0, eq), kv.substr(eq + 1));
      }
    }
    if (out.flags.count("host")) out.config.Set(out.Key("host"), out.flags["host"].as<std::string>());
    if (out.flags.count("port")) out.config.Set(out.Key("port"), std::to_string(out.flags["port"].as<int>()));
    if (out.flags.count("bind")) out.config.Set(out.Key("bind"), out.flags["bind"].as<std::string>());
    out.log_level = out.flags.count("log-level") ? out.flags["log-level"].as<std::string>()
                                                 : out.Get<std::string>("log_level", "info");
  } catch (const ConfigError& e) {
    std::cerr << argv[0] << ": " << e.what() << "\n";
    *exit_code = 2;
    return std::nullopt;
  }
  igms::log::Init(out.name, out.log_level);
  TuneAllocator();
  *exit_code = 0;
  return out;
}

}  // namespace igms::config
