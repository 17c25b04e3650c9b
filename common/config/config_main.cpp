// igms config: reads the lab configuration for scripts (the launcher, systemd, compose).
//   igms config get KEY [--config FILE]      prints the value (a scalar, or YAML)
//   igms config processes [--config FILE]    prints each process's name
//   igms config dump [--config FILE]         prints the whole file as IGMS reads it
//   igms config check [--config FILE]        checks the file for every process in it
//   igms config table [--config FILE]        who runs where: name, program, host, port
//                                            (port '-' for a client, such as the control)
// FILE defaults to $IGMS_CONFIG. Exit status: 0 found (check: every process passed), 1 key
// missing, 2 bad input (check: a process failed).
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "common/base/environment.h"
#include "common/config/exit_codes.h"
#include "common/config/keys.h"
#include "common/config/lab_config.h"
#include "common/process/process.h"
#include "common/version/version.h"

namespace {

// A log line "[video] [error] text" without its prefixes: the text.
std::string Message(std::string line) {
  for (int i = 0; i < 2 && !line.empty() && line[0] == '['; ++i) {
    const auto end = line.find("] ");
    if (end == std::string::npos) break;
    line = line.substr(end + 2);
  }
  return line;
}

// Runs PROGRAM --check-config for one process: "" when it passes, else its problems on one line.
std::string CheckProcess(const igms::config::LabConfig& config, const std::string& file,
                         const std::string& name) {
  const std::string program = config.Get<std::string>("processes." + name + ".program", "");
  if (program.empty()) return "processes." + name + ".program: no program named";
  const std::filesystem::path path = igms::FindProgram(program);
  if (path.empty()) return program + " is not installed (looked beside igms and on PATH)";
  const std::filesystem::path output =
      std::filesystem::temp_directory_path() /
      ("igms-config-check-" + std::to_string(::getpid()) + "-" + name + ".log");
  const std::string failed = igms::RunProgram(
      {path.string(), "--check-config", "--config", file, "--name", name}, output.string());
  std::ifstream in(output);
  std::string problems;
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    if (failed.empty()) continue;  // its OK line
    // Its own name before each problem says nothing here.
    if (line.rfind(program + ": ", 0) == 0) line = line.substr(program.size() + 2);
    problems += (problems.empty() ? "" : "; ") + Message(line);
  }
  in.close();
  std::filesystem::remove(output);
  if (failed.empty()) return "";
  return problems.empty() ? failed : problems;
}

// Every process's program checks its own keys; `lab`'s keys are checked here as well, so a
// missing calibration file is named once even when no program can run.
// One line per process, columns aligned, for people and for `read` in scripts.
int Table(const igms::config::LabConfig& config) {
  struct Row {
    std::string name, program, host, port;
  };
  std::vector<Row> rows = {{"NAME", "PROGRAM", "HOST", "PORT"}};
  for (const auto& name : config.ProcessNames()) {
    const std::string key = "processes." + name + ".";
    const bool serves = config.Find(key + "port").IsDefined();
    rows.push_back({name, config.Get<std::string>(key + "program", "-"),
                    serves ? config.Get<std::string>(key + "host", "127.0.0.1") : "-",
                    serves ? std::to_string(config.Get<int>(key + "port")) : "-"});
  }
  std::size_t w[3] = {0, 0, 0};
  for (const auto& r : rows) {
    w[0] = std::max(w[0], r.name.size());
    w[1] = std::max(w[1], r.program.size());
    w[2] = std::max(w[2], r.host.size());
  }
  for (const auto& r : rows) {
    std::cout << r.name << std::string(w[0] - r.name.size() + 2, ' ') << r.program
              << std::string(w[1] - r.program.size() + 2, ' ') << r.host
              << std::string(w[2] - r.host.size() + 2, ' ') << r.port << "\n";
  }
  return igms::kExitOk;
}

int Check(const igms::config::LabConfig& config, const std::string& file) {
  // The checked programs' log lines are compared without their time.
  ::setenv("IGMS_LOG_TIMESTAMPS", "0", 1);  // NOLINT(concurrency-mt-unsafe): one thread here
  bool ok = true;
  std::vector<igms::config::KeyProblem> lab =
      igms::config::UnknownKeys(config, "", igms::config::CommonKeys());
  for (const auto& p : igms::config::BadValues(config, "", igms::config::CommonKeys(), true)) {
    if (p.message.rfind("lab.", 0) == 0) lab.push_back(p);
  }
  if (lab.empty()) {
    std::cout << "lab: OK\n";
  } else {
    ok = false;
    std::string text;
    for (const auto& p : lab) text += (text.empty() ? "" : "; ") + p.Text();
    std::cout << "lab: FAILED: " << text << "\n";
  }
  const auto names = config.ProcessNames();
  if (names.empty()) {
    std::cout << "processes: FAILED: " << file << " names no process\n";
    ok = false;
  }
  for (const auto& name : names) {
    const std::string problems = CheckProcess(config, file, name);
    ok = ok && problems.empty();
    std::cout << name << ": " << (problems.empty() ? "OK" : "FAILED: " + problems) << "\n";
  }
  return ok ? igms::kExitOk : igms::kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  std::string file = igms::EnvironmentVariable("IGMS_CONFIG").value_or("");
  std::vector<std::string> positional;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--config" && i + 1 < args.size()) {
      file = args[++i];
    } else if (args[i] == "-h" || args[i] == "--help") {
      std::cout
          << "usage: igms config get KEY | processes | table | dump | check  [--config FILE]\n"
             "       igms config --version\n";
      return igms::kExitOk;
    } else if (args[i] == "--version") {
      std::cout << igms::version::Line("igms-config") << "\n";
      return igms::kExitOk;
    } else {
      positional.push_back(args[i]);
    }
  }
  if (positional.empty()) {
    std::cerr << "igms config: say what to do: get KEY, processes, table, dump or check\n";
    return igms::kExitUsage;
  }
  if (file.empty()) {
    std::cerr << "igms config: no configuration file (use --config FILE or set IGMS_CONFIG)\n";
    return igms::kExitUsage;
  }
  try {
    const auto config = igms::config::LabConfig::Load(file);
    const std::string& verb = positional[0];
    if (verb == "get" && positional.size() == 2) {
      const YAML::Node node = config.Find(positional[1]);
      if (!node.IsDefined() || node.IsNull()) {
        std::cerr << "igms config: " << file << ": no key " << positional[1] << "\n";
        return igms::kExitFailure;
      }
      if (node.IsScalar()) {
        std::cout << node.Scalar() << "\n";
      } else {
        YAML::Emitter out;
        out << node;
        std::cout << out.c_str() << "\n";
      }
      return igms::kExitOk;
    }
    if (verb == "processes") {
      for (const auto& name : config.ProcessNames()) std::cout << name << "\n";
      return igms::kExitOk;
    }
    if (verb == "table") return Table(config);
    if (verb == "dump") {
      std::cout << config.Dump() << "\n";
      return igms::kExitOk;
    }
    if (verb == "check") return Check(config, std::filesystem::absolute(file).string());
    std::cerr << "igms config: unknown command (get KEY, processes, table, dump, check)\n";
    return igms::kExitUsage;
  } catch (const igms::config::ConfigError& e) {
    std::cerr << "igms config: " << e.what() << "\n";
    return igms::kExitUsage;
  } catch (const std::exception& e) {  // a file that cannot be read or removed, say
    std::cerr << "igms config: " << e.what() << "\n";
    return igms::kExitFailure;
  }
}
