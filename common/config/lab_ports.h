// The lab's one port table: each process's well-known port, the default of its program's
// --port and the port deploy/lab.yaml gives it. tests/common/config/lab_ports_test.cpp checks
// that deploy/lab.yaml and the docs say the same; change a port here and there together.
#pragma once

#include <cstdint>

namespace igms::config::ports {

inline constexpr std::uint16_t kVideo = 7301;     // igms-video-server
inline constexpr std::uint16_t kObject = 7302;    // igms-object-server
inline constexpr std::uint16_t kSound = 7303;     // igms-sound-server
inline constexpr std::uint16_t kViewer = 7311;    // igms-viewerd
inline constexpr std::uint16_t kJoystick = 7312;  // igms-joystickd
inline constexpr std::uint16_t kRanger = 7313;    // igms-rangerd
inline constexpr std::uint16_t kVoice = 7314;     // igms-voiced
inline constexpr std::uint16_t kPlatform = 7315;  // igms-platformd

// The table by the process's name in the lab file and its program, for tests and tools.
struct LabPort {
  const char* process;
  const char* program;
  std::uint16_t port;
};
inline constexpr LabPort kLabPorts[] = {
    {"video", "igms-video-server", kVideo},    {"object", "igms-object-server", kObject},
    {"sound", "igms-sound-server", kSound},    {"viewer", "igms-viewerd", kViewer},
    {"joystick", "igms-joystickd", kJoystick}, {"ranger", "igms-rangerd", kRanger},
    {"voice", "igms-voiced", kVoice},          {"platform", "igms-platformd", kPlatform},
};

}  // namespace igms::config::ports
