#include "common/config/process_options.h"

#include <malloc.h>
#include <spdlog/spdlog.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "common/base/environment.h"
#include "common/config/exit_codes.h"
#include "common/log/log.h"
#include "common/version/version.h"

namespace igms::config {

namespace po = boost::program_options;

std::uint16_t ProcessOptions::Port(std::uint16_t fallback) const {
  const int port = entry.port.value_or(fallback);
  if (port < 0 || port > 65535) {
    throw config.Error(Key("port"), config.Find(Key("port")), "must be a port number (0-65535)");
  }
  return static_cast<std::uint16_t>(port);
}

std::string ProcessOptions::HostOf(const std::string& process) const {
  return config.Get<std::string>("processes." + process + ".host", ProcessEntry().host);
}

std::uint16_t ProcessOptions::PortOf(const std::string& process) const {
  const std::string key = "processes." + process + ".port";
  const int port = config.Get<int>(key);
  if (port <= 0 || port > 65535) throw config.Error(key, config.Find(key), "must be 1-65535");
  return static_cast<std::uint16_t>(port);
}

LabSecurity SecurityOf(const LabConfig& config, const std::string& name) {
  return SecurityOf(LabOptionsOf(config), config, name);
}

LabSecurity SecurityOf(const LabOptions& lab, const LabConfig& config, const std::string& name) {
  LabSecurity s;
  s.name = name;
  const std::string& tls = lab.tls;
  if (tls == "on" || tls == "true") {
    s.tls = true;
  } else if (tls != "off" && tls != "false") {
    throw config.Error("lab.tls", config.Find("lab.tls"), "must be on or off");
  }
  // systemd's LoadCredential=
  const std::string credentials = EnvironmentVariable("CREDENTIALS_DIRECTORY").value_or("");
  if (!lab.certs.empty()) {
    s.certs_dir = lab.certs;
  } else if (!credentials.empty()) {
    s.certs_dir = credentials;
  } else {
    s.certs_dir = config.ResolvePath("certs");
  }
  const YAML::Node table = config.Find("lab.permissions");
  if (table.IsDefined() && table.IsMap()) {
    for (const auto& kv : table) {
      std::vector<std::string> names;
      if (kv.second.IsSequence()) {
        for (const auto& n : kv.second) names.push_back(n.Scalar());
      } else if (kv.second.IsScalar()) {
        names.push_back(kv.second.Scalar());
      } else if (!kv.second.IsNull()) {
        throw config.Error("lab.permissions." + kv.first.Scalar(), kv.second,
                           "must be a list of certificate names");
      }
      s.permissions.emplace_back(kv.first.Scalar(), std::move(names));
    }
  }
  return s;
}

namespace {
LabSecurity& SecuritySlot() {
  static LabSecurity security;
  return security;
}
}  // namespace

const LabSecurity& ProcessSecurity() { return SecuritySlot(); }
void SetProcessSecurity(LabSecurity security) { SecuritySlot() = std::move(security); }

void TuneAllocator() {
  // Frames of images and large requests are allocated and freed many times a second; above
  // glibc's default mmap threshold each one is a fresh mapping whose pages fault in on every
  // copy. Keeping them on the heap more than halved the time of a 500 KB request.
  // It runs before the program starts a thread: mallopt races only with a concurrent malloc.
  mallopt(M_MMAP_THRESHOLD, 64 << 20);   // NOLINT(concurrency-mt-unsafe): no thread yet
  mallopt(M_TRIM_THRESHOLD, 256 << 20);  // NOLINT(concurrency-mt-unsafe): no thread yet
}

namespace {

std::string ProgramName(const char* argv0) {
  return std::filesystem::path(argv0).filename().string();
}

// The keys the --set flags name, checked like the file's (a --set that names no key is a typo
// too). Returns the problems.
std::vector<KeyProblem> UnknownSetKeys(const std::vector<std::string>& sets,
                                       const std::string& name, const Keys& keys) {
  std::vector<KeyProblem> problems;
  for (const auto& kv : sets) {
    const std::string key = kv.substr(0, kv.find('='));
    LabConfig probe;
    probe.Set(key, "0");
    for (auto problem : UnknownKeys(probe, name, keys)) {
      problem.where = "--set " + key;
      problems.push_back(problem);
    }
  }
  return problems;
}

// The keys for --help: "  poll_hz (number, default 50): orientation polling rate".
std::string KeysHelp(const Keys& keys) {
  static const char* const kTypes[] = {"string", "integer", "number", "true/false",
                                       "list",   "map",     "path",   "output path"};
  std::string text = "Configuration keys (processes.NAME.KEY, and lab.KEY):\n";
  for (const auto& spec : keys.specs()) {
    text += "  " + spec.key + " (" + kTypes[static_cast<int>(spec.type)];
    if (!spec.choices.empty()) {
      std::string list;
      for (const auto& c : spec.choices) list += (list.empty() ? "" : "|") + c;
      text += ": " + list;
    }
    if (!spec.default_value.empty()) text += ", default " + spec.default_value;
    if (!spec.flag.empty()) text += ", flag --" + spec.flag;
    text += "): " + spec.help + "\n";
  }
  return text;
}

}  // namespace

std::optional<ProcessOptions> ParseProcessOptions(int argc, char** argv,
                                                  const std::string& default_name,
                                                  const std::string& summary,
                                                  const po::options_description& extra,
                                                  const Keys& component_keys, int* exit_code) {
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
      "log-level", po::value<std::string>(),
      "trace, debug, info, warn, error (default: the file's log_level, else info)")(
      "check-config", po::bool_switch(),
      "check the configuration for this process, print OK or the problems, and exit (0 or 2)")(
      "allow-unknown-keys", po::bool_switch(),
      "warn about keys nothing reads instead of refusing to start");
  po::options_description all;
  all.add(common).add(extra);
  const std::string program = ProgramName(argv[0]);

  ProcessOptions out;
  try {
    po::store(po::parse_command_line(argc, argv, all), out.flags);
    po::notify(out.flags);
  } catch (const po::error& e) {
    std::cerr << argv[0] << ": " << e.what() << " (see --help)\n";
    *exit_code = kExitUsage;
    return std::nullopt;
  }
  const Keys common_keys = CommonKeys(&out.lab, &out.entry);
  Keys keys = common_keys;
  keys.Merge(component_keys);
  if (out.flags.count("help")) {
    std::cout << summary << "\n\n" << all << "\n" << KeysHelp(keys) << "\n";
    *exit_code = kExitOk;
    return std::nullopt;
  }
  if (out.flags.count("version")) {
    std::cout << version::Line(version::ProgramName()) << "\n";
    *exit_code = 0;
    return std::nullopt;
  }
  out.name = out.flags["name"].as<std::string>();
  out.check_only = out.flags["check-config"].as<bool>();
  const auto fail = [&](const std::vector<KeyProblem>& problems) {
    for (const auto& p : problems) std::cerr << program << ": " << p.Text() << "\n";
    *exit_code = kExitUsage;
    return std::nullopt;
  };
  try {
    if (out.check_only && !out.flags.count("config")) {
      return fail({{"", "--check-config needs the file to check: --config FILE"}});
    }
    if (out.flags.count("config")) {
      out.config = LabConfig::Load(out.flags["config"].as<std::string>());
      if (out.check_only && !out.config.Has("processes." + out.name)) {
        return fail({{out.config.source(), "no process named " + out.name + " under processes"}});
      }
    }
    std::vector<std::string> sets;
    if (out.flags.count("set")) sets = out.flags["set"].as<std::vector<std::string>>();
    // Unknown keys are judged in the file before --set adds its own (with no line of the file).
    std::vector<KeyProblem> unknown = UnknownKeys(out.config, out.name, keys);
    for (const auto& kv : sets) {
      const auto eq = kv.find('=');
      if (eq == std::string::npos || eq == 0) {
        throw ConfigError("--set expects KEY=VALUE, got '" + kv + "'");
      }
      out.config.Set(kv.substr(0, eq), kv.substr(eq + 1));
    }
    for (const auto& p : UnknownSetKeys(sets, out.name, keys)) unknown.push_back(p);
    if (out.flags.count("host"))
      out.config.Set(out.Key("host"), out.flags["host"].as<std::string>());
    if (out.flags.count("port"))
      out.config.Set(out.Key("port"), std::to_string(out.flags["port"].as<int>()));
    if (out.flags.count("bind"))
      out.config.Set(out.Key("bind"), out.flags["bind"].as<std::string>());
    const bool allow_unknown = out.flags["allow-unknown-keys"].as<bool>();
    std::vector<KeyProblem> problems = BadValues(out.config, out.name, keys, out.check_only);
    if (!unknown.empty() && (out.check_only || !allow_unknown)) {
      problems.insert(problems.begin(), unknown.begin(), unknown.end());
      if (!out.check_only) {
        problems.push_back(
            {"", "refusing to start on unknown keys (--allow-unknown-keys to go on)"});
      }
    }
    if (!problems.empty()) return fail(problems);
    common_keys.Read(out);
    out.log_level = out.entry.log_level.empty() ? out.lab.log_level : out.entry.log_level;
    // A check prints its result, not the process's chatter.
    igms::log::Init(out.name, out.check_only ? "warn" : out.log_level);
    for (const auto& p : unknown) {
      if (!out.check_only) spdlog::warn("{} (going on: --allow-unknown-keys)", p.Text());
    }
    component_keys.Read(out);
    SetProcessSecurity(SecurityOf(out.lab, out.config, out.name));
  } catch (const ConfigError& e) {
    std::cerr << program << ": " << e.what() << "\n";
    *exit_code = kExitUsage;
    return std::nullopt;
  }
  TuneAllocator();
  *exit_code = kExitOk;
  return out;
}

int CheckPassed(const ProcessOptions& process) {
  std::cout << process.config.source() << ": OK for processes." << process.name << "\n";
  return kExitOk;
}

}  // namespace igms::config
