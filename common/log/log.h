// Logging for every IGMS process: spdlog to stderr, one line per event, with the process's
// name and the level, e.g. "[video] [warning] closing 127.0.0.1:5312: bad frame ...".
// Under systemd the journal adds its own timestamps; IGMS_LOG_TIMESTAMPS=0 drops ours.
#pragma once

#include <string>

namespace igms::log {

// Sets up the default logger. level: trace, debug, info, warn, error, critical, off.
// Returns false (and keeps "info") for an unknown level name.
bool Init(const std::string& process_name, const std::string& level = "info");

}  // namespace igms::log
