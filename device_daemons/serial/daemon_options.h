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

// What the keys and flags above say (flags over keys over these defaults), from which
// ReadDaemonOptions picks the source. --simulate and --sim-only are flags only.
struct DaemonConfig {
  std::string serial;  // a port, or "simulate"
  unsigned baud = SerialLinkOptions().baud;
  std::string sim_port;  // empty: a fresh temporary link
  std::string replay;    // the key's made absolute
  double replay_speed = DaemonOptions().replay_speed;
  bool loop = false;
  std::string record;  // the key's made absolute
  std::chrono::milliseconds silence = SerialLinkOptions().silence_timeout;
};

// The keys above (processes.NAME.serial, .baud, .sim_port, .replay, .replay_speed, .loop,
// .record, .silence_ms) and max_frame_bytes (net::ServerKeys), bound to `config` with
// their flags.
config::Keys DaemonKeys(DaemonConfig* config);

// Adds the flags above to `flags`.
void AddDaemonFlags(boost::program_options::options_description* flags);

// The daemon's options from what DaemonKeys read into `config` and the --simulate and
// --sim-only flags of `process`. False with a message when they do not name exactly one
// source, or a value is invalid.
bool ReadDaemonOptions(const config::ProcessOptions& process, const DaemonConfig& config,
                       const std::string& device, DaemonOptions* out, std::string* error);

}  // namespace igms::devices
