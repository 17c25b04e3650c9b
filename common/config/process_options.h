// The command line every IGMS process shares, and its section of the lab configuration.
//
//   PROGRAM --config lab.yaml --name video [--set processes.video.port=7400]...
//           [--host H] [--port P] [--bind ADDRESS] [--log-level debug] [component flags]
//   PROGRAM --help | --version
//
// --host, --port and --bind are shorthands for processes.NAME.host, .port and .bind;
// --set overrides any key. Flags win over the file. Without --config the process runs on
// its built-in defaults.
//
// A key in `lab` or processes.NAME that neither the common keys nor the component's Keys
// declare stops the process (exit 2) unless --allow-unknown-keys is given (then it warns).
// --check-config checks the file for this process and exits 0 or 2 without starting it:
// ParseProcessOptions checks the keys, their types and that path keys name files that exist;
// the main then validates its options as it would to start, and returns CheckPassed().
#pragma once

#include <boost/program_options.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/config/keys.h"
#include "common/config/lab_config.h"

namespace igms::config {

struct ProcessOptions {
  LabConfig config;
  std::string name;       // the process's entry under "processes"
  LabOptions lab;         // lab.token, lab.calibration, ...: the keys every process shares
  ProcessEntry entry;     // processes.NAME.host, .port, ...: the keys every process has
  std::string log_level;  // already applied by Parse: entry's, else lab's
  boost::program_options::variables_map flags;
  bool check_only = false;  // --check-config: validate, report, and do not start

  std::string Key(const std::string& sub) const { return "processes." + name + "." + sub; }
  template <class T>
  T Get(const std::string& sub, const T& fallback) const {
    return config.Get<T>(Key(sub), fallback);
  }
  // The port this process listens on: entry.port, else `fallback`. Throws ConfigError for
  // one outside 0-65535.
  std::uint16_t Port(std::uint16_t fallback) const;
  // Host and port of another process of the lab, for clients.
  std::string HostOf(const std::string& process) const;
  std::uint16_t PortOf(const std::string& process) const;
};

// The lab's transport security for one process (docs/security.md).
struct LabSecurity {
  bool tls = false;       // lab.tls: on
  std::string certs_dir;  // lab.certs, made absolute
  std::string name;       // whose certificate this process presents
  // lab.permissions: method or "Service.*" pattern -> certificate names.
  std::vector<std::pair<std::string, std::vector<std::string>>> permissions;
};
// From lab.tls, lab.certs and lab.permissions (of `config`, whose lab keys `lab` holds);
// throws ConfigError for a bad value.
LabSecurity SecurityOf(const LabOptions& lab, const LabConfig& config, const std::string& name);
// The same for a lab file alone.
LabSecurity SecurityOf(const LabConfig& config, const std::string& name);
// The process-wide settings every server and client of common/net takes unless told
// otherwise: ParseProcessOptions sets them, so no component has to pass them on.
const LabSecurity& ProcessSecurity();
void SetProcessSecurity(LabSecurity security);

// Keeps large message buffers on the heap (see the .cpp). ParseProcessOptions calls it;
// programs that don't use it (benchmarks) call it themselves.
void TuneAllocator();

// Parses the shared flags plus `extra`, loads the configuration, applies overrides, refuses
// keys that neither CommonKeys() nor `keys` declare, fills `lab`, `entry` and the fields
// `keys` binds and starts logging (level: --log-level, else processes.NAME.log_level, else
// lab.log_level, else info).
// Returns nullopt after printing help or the version (exit 0) or an error (exit 2):
// *exit_code says which.
std::optional<ProcessOptions> ParseProcessOptions(
    int argc, char** argv, const std::string& default_name, const std::string& summary,
    const boost::program_options::options_description& extra, const Keys& keys, int* exit_code);

// For --check-config, once the main has validated everything it would validate to start:
// prints one line saying the configuration is good for this process and returns 0.
int CheckPassed(const ProcessOptions& process);

}  // namespace igms::config
