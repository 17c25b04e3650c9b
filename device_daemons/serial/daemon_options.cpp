#include "device_daemons/serial/daemon_options.h"

#include <unistd.h>

#include <filesystem>

#include "common/net/process_server.h"

namespace igms::devices {

namespace po = boost::program_options;

bool DaemonOptions::Check(std::string* error) const {
  if (source == SourceKind::kReplay) {
    if (replay_file.empty()) {
      *error = "--replay needs a file";
      return false;
    }
    if (!(replay_speed >= 0)) {
      *error = "--replay-speed must be >= 0";
      return false;
    }
    return true;
  }
  return link.Check(error);
}

config::Keys DaemonKeys(DaemonConfig* c) {
  config::Keys keys = net::ServerKeys();
  keys.Bind("serial", &c->serial, "serial port of the device, or simulate", "serial");
  keys.Bind("baud", &c->baud, "baud rate", "baud");
  keys.Bind("sim_port", &c->sim_port,
            "link path of the simulator's pseudo-terminal (default: a fresh temporary one)",
            "sim-port");
  keys.BindPath("replay", &c->replay, "publish readings from this recording", "replay");
  keys.Bind("replay_speed", &c->replay_speed,
            "replay at this many times the original rate; 0 = at once", "replay-speed");
  keys.Bind("loop", &c->loop, "repeat the replay", "loop");
  keys.BindPath("record", &c->record, "record every reading to this file", "record",
                config::KeyType::kOutputPath);
  keys.Bind("silence_ms", &c->silence, "watchdog: the device is stale after this silence",
            "silence-ms");
  return keys;
}

void AddDaemonFlags(po::options_description* flags) {
  flags->add_options()("serial", po::value<std::string>(),
                       "serial port of the device, or \"simulate\"")("baud", po::value<unsigned>(),
                                                                     "baud rate (default 9600)")(
      "simulate", po::bool_switch(), "run the device's simulator on a pseudo-terminal")(
      "sim-port", po::value<std::string>(), "link path of the simulator's pseudo-terminal")(
      "sim-only", po::bool_switch(),
      "with --simulate: the simulator alone on its pseudo-terminal, for other software")(
      "replay", po::value<std::string>(), "publish readings from a recording")(
      "replay-speed", po::value<double>(),
      "replay at this many times the original rate; 0 = at once")(
      "loop", po::bool_switch(), "repeat the replay")("record", po::value<std::string>(),
                                                      "record every reading to this file")(
      "silence-ms", po::value<int>(), "watchdog: the device is stale after this silence");
}

bool ReadDaemonOptions(const config::ProcessOptions& p, const DaemonConfig& c,
                       const std::string& device, DaemonOptions* out, std::string* error) {
  const auto& f = p.flags;
  std::string serial = c.serial;
  const bool simulate = (f.count("simulate") && f["simulate"].as<bool>()) || serial == "simulate";
  if (simulate && serial == "simulate") serial.clear();
  const int sources = (simulate ? 1 : 0) + (!serial.empty() ? 1 : 0) + (!c.replay.empty() ? 1 : 0);
  if (sources != 1) {
    *error = sources == 0
                 ? "name where the " + device + " is: --serial PORT, --simulate or --replay FILE"
                 : "name only one of --serial, --simulate and --replay";
    return false;
  }
  DaemonOptions o;
  o.source = simulate          ? SourceKind::kSimulate
             : !serial.empty() ? SourceKind::kSerial
                               : SourceKind::kReplay;
  o.link.baud = c.baud;
  o.link.silence_timeout = c.silence;
  if (o.source == SourceKind::kSerial) o.link.port = serial;
  if (o.source == SourceKind::kSimulate) {
    o.link.port = c.sim_port;
    if (o.link.port.empty()) {
      o.link.port = (std::filesystem::temp_directory_path() /
                     ("igms-" + device + "-sim-" + std::to_string(::getpid())))
                        .string();
    }
  }
  o.sim_only = f.count("sim-only") && f["sim-only"].as<bool>();
  if (o.sim_only && o.source != SourceKind::kSimulate) {
    *error = "--sim-only runs the simulator alone: it needs --simulate";
    return false;
  }
  o.replay_file = c.replay;
  o.replay_speed = c.replay_speed;
  o.loop = c.loop;
  o.record_file = c.record;
  if (!o.Check(error)) return false;
  *out = o;
  return true;
}

}  // namespace igms::devices
