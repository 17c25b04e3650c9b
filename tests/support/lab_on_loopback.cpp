#include "tests/support/lab_on_loopback.h"

#include <fmt/format.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fstream>

namespace igms::testing {
namespace {

struct Entry {
  const char* name;
  const char* program;
  const char* lines;  // the entry's own keys
  const char* after;  // the process whose port it needs first, or ""
};

// deploy/lab.yaml's processes, with the sound mixed into nothing.
const Entry kEntries[] = {
    {"platform", "igms-platformd", "    serial: simulate\n", ""},
    {"viewer", "igms-viewerd", "    serial: simulate\n", ""},
    {"joystick", "igms-joystickd", "    serial: simulate\n", ""},
    {"voice", "igms-voiced", "    serial: simulate\n", ""},
    {"sound", "igms-sound-server", "    output: \"null\"\n", ""},
    {"ranger", "igms-rangerd", "    serial: simulate\n    platform: platform\n", "platform"},
    {"video", "igms-video-server", "    backend: sim\n    platform: platform\n", "platform"},
    {"object", "igms-object-server", "    video: video\n", "video"},
};

}  // namespace

LabOnLoopback::LabOnLoopback(std::string control, std::string video)
    : control_(std::move(control)), video_(std::move(video)) {}

void LabOnLoopback::Set(const std::string& name, std::string lines, std::vector<std::string> args) {
  lines_[name] = std::move(lines);
  args_[name] = std::move(args);
}

std::string LabOnLoopback::Text(bool with_ports) const {
  std::string t = fmt::format(
      "lab:\n  token: \"\"\n  calibration: {}\n  log_level: info\nprocesses:\n  control:\n"
      "    program: igms-control\n{}",
      ThesisCalibration(), control_);
  for (const Entry& e : kEntries) {
    auto port = ports_.find(e.name);
    auto own = lines_.find(e.name);
    t += fmt::format("  {}:\n    program: {}\n    host: 127.0.0.1\n    port: {}\n{}{}", e.name,
                     e.program, with_ports && port != ports_.end() ? port->second : 0,
                     own != lines_.end() ? own->second : std::string(e.lines),
                     std::string(e.name) == "video" ? video_ : "");
  }
  return t;
}

bool LabOnLoopback::Launch(const std::string& name, uint16_t port) {
  std::vector<std::string> args = {"--config", dir_.File("lab.yaml"), "--name", name,
                                   "--port",   std::to_string(port)};
  if (auto more = args_.find(name); more != args_.end()) {
    args.insert(args.end(), more->second.begin(), more->second.end());
  }
  processes_[name] = std::make_unique<ChildProcess>(
      [&] {
        for (const Entry& e : kEntries) {
          if (e.name == name) return std::string(e.program);
        }
        return std::string();
      }(),
      args);
  const uint16_t listening = processes_[name]->WaitListening();
  if (listening == 0) {
    error_ = name + " did not listen; its log:\n" + processes_[name]->Log();
    return false;
  }
  ports_[name] = listening;
  return true;
}

bool LabOnLoopback::Start() {
  // Each process reads the lab file as it stands when it starts: the ports of those it
  // talks to are in it by then.
  for (const Entry& e : kEntries) {
    std::ofstream(dir_.File("lab.yaml")) << Text(true);
    if (!Launch(e.name, 0)) return false;
  }
  std::ofstream(dir_.File("lab.yaml")) << Text(true);
  return true;
}

void LabOnLoopback::WriteWithoutStarting() {
  for (const Entry& e : kEntries) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    if (fd >= 0 && ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0) {
      ports_[e.name] = ntohs(address.sin_port);
    }
    if (fd >= 0) ::close(fd);
  }
  std::ofstream(dir_.File("lab.yaml")) << Text(true);
}

void LabOnLoopback::Kill(const std::string& name) { processes_.at(name)->Kill(); }

bool LabOnLoopback::Restart(const std::string& name) {
  processes_.erase(name);
  return Launch(name, ports_.at(name));
}

}  // namespace igms::testing
