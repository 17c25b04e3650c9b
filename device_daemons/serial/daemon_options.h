// The command line and configuration keys every device daemon shares, and where its
// readings come from:
//
//   --serial PORT --baud 9600   a real device (processes.NAME.serial, .baud)
//   --simulate                  the daemon starts its own simulator on a pseudo-terminal
//                               (processes.NAME.serial: simulate); --sim-port PATH names
//                               the pseudo-terminal's link (default: a fresh temporary one)
//   --sim-only                  with --simulate: the simulator alone, for other software on
//                               the link (`igms sim`); no driver reads it, SimService serves
//   --replay FILE               readings from a recording (processes.NAME.replay), at
//                               --replay-speed times the original rate (0 = at once),
//                               --loop to repeat
//   --record FILE               also writes every reading to FILE (processes.NAME.record)
//   --silence-ms N              watchdog: silent this long = stale (processes.NAME.silence_ms)
//
// Exactly one source must be named; the error says what was missing.
#pragma once

#include <boost/program_options.hpp>
#include <chrono>
#include <string>

#include "common/config/process_options.h"
#include "device_daemons/serial/serial_link.h"

namespace igms::devices {

enum class SourceKind { kSerial, kSimulate, kReplay };

struct DaemonOptions {
  SourceKind source = SourceKind::kSimulate;
  SerialLinkOptions link;  // kSerial; for kSimulate the port is the simulator's link
  std::string replay_file;
  double replay_speed = 1.0;
  bool loop = false;
  std::string record_file;
  bool sim_only = false;  // the simulator alone on its pseudo-terminal (igms sim)
  bool Check(std::string* error) const;
};

// The keys above (processes.NAME.serial, .baud, .sim_port, .replay, .replay_speed, .loop,
// .record, .silence_ms), which ReadDaemonOptions reads.
config::Keys DaemonKeys();

// Adds the flags above to `flags`.
void AddDaemonFlags(boost::program_options::options_description* flags);

// Reads them (flags over configuration keys) for the process named in `process`.
// False with a message when they do not name exactly one source, or a value is invalid.
bool ReadDaemonOptions(const config::ProcessOptions& process, const std::string& device,
                       DaemonOptions* out, std::string* error);

}  // namespace igms::devices
