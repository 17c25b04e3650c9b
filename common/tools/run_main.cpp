// igms run: starts one process of the lab file, the one launch path of the launcher
// (deploy/lab up), the systemd units (igms@NAME.service) and docker-compose.
//
//   igms run NAME [--config FILE] [-- EXTRA ARGS...]
//
// Reads processes.NAME.program and replaces itself with that program (found beside igms,
// then on PATH), run as `PROGRAM --config FILE --name NAME EXTRA...`, so the pid a
// supervisor holds is the process's own and its signals reach it. FILE defaults to
// $IGMS_CONFIG. Exit status 2 when the file, the process or its program cannot be found.
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "common/base/environment.h"
#include "common/base/errno_text.h"
#include "common/config/exit_codes.h"
#include "common/config/lab_config.h"
#include "common/process/process.h"
#include "common/version/version.h"

namespace {

constexpr const char* kUsage =
    "usage: igms run NAME [--config FILE] [-- EXTRA ARGS...]\n"
    "Starts processes.NAME of the lab file (default $IGMS_CONFIG) as\n"
    "PROGRAM --config FILE --name NAME EXTRA...\n";

int Usage(const std::string& message) {
  std::cerr << "igms run: " << message << "\n" << kUsage;
  return igms::kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  std::string file = igms::EnvironmentVariable("IGMS_CONFIG").value_or("");
  std::string name;
  std::vector<std::string> extra;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--") {
      extra.assign(argv + i + 1, argv + argc);
      break;
    }
    if (arg == "-h" || arg == "--help") {
      std::cout << kUsage;
      return igms::kExitOk;
    }
    if (arg == "--version") {
      std::cout << igms::version::Line("igms-run") << "\n";
      return igms::kExitOk;
    }
    if (arg == "--config" && i + 1 < argc) {
      file = argv[++i];
    } else if (arg.rfind("--config=", 0) == 0) {
      file = arg.substr(9);
    } else if (!arg.empty() && arg[0] != '-' && name.empty()) {
      name = arg;
    } else {
      return Usage("unexpected argument '" + arg + "'");
    }
  }
  if (name.empty()) return Usage("name the process to run");
  if (file.empty()) return Usage("no configuration file (use --config FILE or set IGMS_CONFIG)");
  std::string program;
  try {
    const auto config = igms::config::LabConfig::Load(file);
    if (!config.Find("processes." + name).IsDefined()) {
      std::string names;
      for (const auto& n : config.ProcessNames()) names += " " + n;
      std::cerr << "igms run: " << file << " has no process '" << name << "' (it has:" << names
                << ")\n";
      return igms::kExitUsage;
    }
    program = config.Get<std::string>("processes." + name + ".program");
  } catch (const igms::config::ConfigError& e) {
    std::cerr << "igms run: " << e.what() << "\n";
    return igms::kExitUsage;
  }
  // A program name, never a path: the lab file chooses among the lab's programs only.
  if (program.empty() || program.find('/') != std::string::npos) {
    std::cerr << "igms run: processes." << name << ".program '" << program
              << "' is not a program name\n";
    return igms::kExitUsage;
  }
  const std::filesystem::path path = igms::FindProgram(program);
  if (path.empty()) {
    std::cerr << "igms run: " << program << " (processes." << name
              << ") is not installed (looked beside igms and on PATH)\n";
    return igms::kExitUsage;
  }
  // The child sees the file by an absolute path: its relative paths are the file's folder's.
  const std::string absolute = std::filesystem::absolute(file).string();
  std::vector<std::string> args = {program, "--config", absolute, "--name", name};
  args.insert(args.end(), extra.begin(), extra.end());
  std::vector<char*> raw;
  raw.reserve(args.size() + 1);
  for (auto& a : args) raw.push_back(a.data());
  raw.push_back(nullptr);
  execv(path.c_str(), raw.data());
  std::cerr << "igms run: cannot run " << path << ": " << igms::ErrnoText(errno) << "\n";
  return igms::kExitUnavailable;
}
