// igms sim: one device simulator alone on a pseudo-terminal, with no daemon reading it, so
// other software for that device (a CerealBox driver, a terminal program, a lab's own tools)
// can be tried against it before the hardware is at hand (docs/devices.md).
//
//   igms sim joystick|viewer|ranger|platform|voice --link PATH [--port P] [--config FILE]
//            [-- EXTRA DAEMON FLAGS...]
//
// Runs the device's daemon with --simulate --sim-port PATH --sim-only: the simulator's
// pseudo-terminal is published at PATH, and the daemon's server on port P (default the
// lab's port for the device) serves igms.devices.SimService.Inject, the operator input and
// faults (igmsctl call SimService.Inject '{...}'), but no driver opens the link. With
// --config FILE the device's section of the lab file (processes.DEVICE) gives the
// simulator's keys.
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "common/base/errno_text.h"
#include "common/config/exit_codes.h"
#include "common/process/process.h"
#include "common/version/version.h"

namespace {

constexpr const char* kUsage =
    "usage: igms sim joystick|viewer|ranger|platform|voice --link PATH [--port P]\n"
    "                [--config FILE] [-- EXTRA DAEMON FLAGS...]\n"
    "The device's simulator alone on a pseudo-terminal published at PATH, for other\n"
    "software; its SimService on port P (default the lab's port for the device).\n";

int Usage(const std::string& message) {
  std::cerr << "igms sim: " << message << "\n" << kUsage;
  return igms::kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  const std::map<std::string, std::string> daemons = {{"joystick", "igms-joystickd"},
                                                      {"viewer", "igms-viewerd"},
                                                      {"ranger", "igms-rangerd"},
                                                      {"platform", "igms-platformd"},
                                                      {"voice", "igms-voiced"}};
  std::string device, link, port, config;
  std::vector<std::string> extra;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      std::cout << kUsage;
      return igms::kExitOk;
    }
    if (arg == "--version") {
      std::cout << igms::version::Line("igms-sim") << "\n";
      return igms::kExitOk;
    }
    if (arg == "--") {
      extra.assign(argv + i + 1, argv + argc);
      break;
    }
    const bool has_value = i + 1 < argc;
    if (arg == "--link" && has_value) {
      link = argv[++i];
    } else if (arg == "--port" && has_value) {
      port = argv[++i];
    } else if (arg == "--config" && has_value) {
      config = argv[++i];
    } else if (!arg.empty() && arg[0] != '-' && device.empty()) {
      device = arg;
    } else {
      return Usage("unexpected argument '" + arg + "'");
    }
  }
  if (device.empty()) return Usage("name the device");
  const auto daemon = daemons.find(device);
  if (daemon == daemons.end()) return Usage("no simulator for '" + device + "'");
  if (link.empty()) return Usage("--link PATH: where to publish the pseudo-terminal");
  const std::filesystem::path program = igms::FindProgram(daemon->second);
  if (program.empty()) {
    std::cerr << "igms sim: " << daemon->second << " is not installed\n";
    return igms::kExitUsage;
  }
  std::vector<std::string> args = {daemon->second, "--name", device,      "--simulate",
                                   "--sim-port",   link,     "--sim-only"};
  if (!config.empty()) {
    args.push_back("--config");
    args.push_back(config);
  }
  if (!port.empty()) {
    args.push_back("--port");
    args.push_back(port);
  }
  args.insert(args.end(), extra.begin(), extra.end());
  std::vector<char*> raw;
  raw.reserve(args.size() + 1);
  for (auto& a : args) raw.push_back(a.data());
  raw.push_back(nullptr);
  execv(program.c_str(), raw.data());
  std::cerr << "igms sim: cannot run " << program << ": " << igms::ErrnoText(errno) << "\n";
  return igms::kExitUnavailable;
}
