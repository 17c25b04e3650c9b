// The configuration keys a component reads, declared next to the options struct they fill
// (docs/configuration.md). One declaration gives a key its type, default and help, lets a
// process refuse keys nobody reads (a typo would otherwise fall back to a default in
// silence), lets `--check-config` check the file, and can bind the key, and the flag that
// overrides it, to a field of the options struct:
//
//   config::Keys RangerKeys(RangerDaemonOptions* o) {
//     config::Keys keys;
//     keys.Bind("poll_hz", &o->poll_hz, "also range continuously at this rate", "poll-hz");
//     keys.Path("scene", "simulator: the site's scene file");  // read by the component
//     return keys;
//   }
//
// Keys are relative to processes.NAME, or absolute when they start with "lab.". A dotted key
// ("edges.sigma") is a key of a nested map. The process's own keys and `lab` are judged; the
// other processes' sections belong to other programs.
#pragma once

#include <chrono>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

namespace boost::program_options {
class variables_map;
}  // namespace boost::program_options

namespace igms::config {

class LabConfig;
struct ProcessOptions;

enum class KeyType {
  kString,
  kInt,
  kNumber,
  kBool,
  kList,        // a YAML sequence
  kMap,         // a YAML map whose keys the component reads itself
  kPath,        // a file or folder the process reads: --check-config checks that it exists
  kOutputPath,  // a file the process writes (created when missing)
};

struct KeySpec {
  std::string key;  // "poll_hz" (in processes.NAME) or "lab.calibration"
  KeyType type = KeyType::kString;
  std::string default_value;  // as text, for help and docs ("" when there is none)
  std::string help;
  std::vector<std::string> choices;  // for a string: the values accepted (empty: any)
  std::string flag;                  // the command-line flag that overrides it, if any
};

// A problem found in a configuration, with the place it was found ("lab.yaml:12").
struct KeyProblem {
  std::string where;
  std::string message;
  std::string Text() const { return where.empty() ? message : where + ": " + message; }
};

namespace detail {
// Where bound keys are read from: a lab file, the process's section in it, and its flags
// (none for a tool that reads the file without being one of its processes).
struct KeySource {
  const LabConfig& config;
  const std::string& name;
  const boost::program_options::variables_map* flags = nullptr;
};
}  // namespace detail

class Keys {
 public:
  // A key the component reads with its own code.
  Keys& Add(const std::string& key, KeyType type, const std::string& default_value,
            const std::string& help);
  // A string key that takes one of `choices`.
  Keys& Choice(const std::string& key, std::vector<std::string> choices,
               const std::string& default_value, const std::string& help);
  // A file or folder the process reads (relative to the configuration file's folder).
  Keys& Path(const std::string& key, const std::string& help) {
    return Add(key, KeyType::kPath, "", help);
  }
  // Binds a key to a field: Read() sets the field from the flag when it is given, else from
  // the key when it is set, else leaves the field's value (the default). A bool flag is a
  // switch that can only turn the field on. T: bool, int, unsigned, double, float,
  // std::string, std::size_t, std::chrono::milliseconds (an integer key, "..._ms"), the
  // lists std::vector<double>, std::vector<int> and std::vector<bool> (a YAML list; the flag
  // a string of numbers separated by spaces or commas, 0 or 1 for a bool), and
  // std::optional<int> (empty when neither the flag nor the key is given).
  template <class T>
  Keys& Bind(const std::string& key, T* field, const std::string& help,
             const std::string& flag = "");
  // A bound string key that takes one of `choices`.
  Keys& BindChoice(const std::string& key, std::string* field, std::vector<std::string> choices,
                   const std::string& help, const std::string& flag = "");
  // Binds a key naming a file or folder: the flag's value is taken as given (relative to the
  // working folder), the key's is made absolute against the configuration file's folder.
  // `type`: kPath (read: --check-config checks that it exists), kOutputPath (written), or
  // kString (a pattern or a name that need not exist as written: resolved all the same).
  Keys& BindPath(const std::string& key, std::string* field, const std::string& help,
                 const std::string& flag = "", KeyType type = KeyType::kPath);
  // Another component's keys (a daemon's own keys after the ones every daemon shares).
  Keys& Merge(const Keys& other);
  // The declarations alone, bound to nothing: Read() on them sets no field.
  Keys Declarations() const;

  // Fills every bound field (flags over the file over the defaults). Throws ConfigError,
  // naming file, line and key, for a value of the wrong type.
  void Read(const ProcessOptions& process) const;
  // The same from a lab file alone, without flags, for a tool that reads the file without
  // being one of its processes (`name`: the section its own keys are read from).
  void Read(const LabConfig& config, const std::string& name = "") const;

  const KeySpec* Find(const std::string& key) const;
  const std::vector<KeySpec>& specs() const { return specs_; }

 private:
  KeySpec& Declare(const std::string& key, KeyType type, const std::string& default_value,
                   const std::string& help);

  std::vector<KeySpec> specs_;
  std::vector<std::function<void(const detail::KeySource&)>> readers_;
};

namespace detail {
template <class T>
struct IsVector : std::false_type {};
template <class T>
struct IsVector<std::vector<T>> : std::true_type {};
template <class T>
struct IsOptional : std::false_type {};
template <class T>
struct IsOptional<std::optional<T>> : std::true_type {};
template <class T>
KeyType TypeOf() {
  if constexpr (IsOptional<T>::value)
    return TypeOf<typename T::value_type>();
  else if constexpr (IsVector<T>::value)
    return KeyType::kList;
  else if constexpr (std::is_same_v<T, bool>)
    return KeyType::kBool;
  else if constexpr (std::is_integral_v<T> || std::is_same_v<T, std::chrono::milliseconds>)
    return KeyType::kInt;  // milliseconds: an integer key ("..._ms")
  else if constexpr (std::is_floating_point_v<T>)
    return KeyType::kNumber;
  else
    return KeyType::kString;
}
template <class T>
std::string DefaultText(const T& value) {
  if constexpr (IsOptional<T>::value) {
    return value ? DefaultText(*value) : "";
  } else if constexpr (IsVector<T>::value) {
    if (value.empty()) return "";
    std::ostringstream out;
    out << "[";
    for (std::size_t i = 0; i < value.size(); ++i) out << (i ? ", " : "") << value[i];
    out << "]";
    return out.str();
  } else if constexpr (std::is_same_v<T, std::chrono::milliseconds>) {
    return std::to_string(value.count());
  } else if constexpr (std::is_same_v<T, bool>)
    return value ? "true" : "false";
  else if constexpr (std::is_same_v<T, std::string>)
    return value;
  else {
    std::ostringstream out;
    out << value;
    return out.str();
  }
}
// Defined in keys.cpp for the types Bind takes.
template <class T>
void ReadBound(const KeySource& source, const KeySpec& spec, T* field);
}  // namespace detail

template <class T>
Keys& Keys::Bind(const std::string& key, T* field, const std::string& help,
                 const std::string& flag) {
  KeySpec& spec = Declare(key, detail::TypeOf<T>(), detail::DefaultText(*field), help);
  spec.flag = flag;
  readers_.push_back([spec = spec, field](const detail::KeySource& source) {
    detail::ReadBound(source, spec, field);
  });
  return *this;
}

// The keys in `lab` every process shares. ParseProcessOptions reads them into
// ProcessOptions::lab; a tool that reads a lab file without running as one of its processes
// calls LabOptionsOf.
struct LabOptions {
  std::string token;        // every client presents it; empty: none
  std::string tls = "off";  // on or off (SecurityOf)
  std::string certs;        // absolute; empty: $CREDENTIALS_DIRECTORY, else certs beside the file
  std::string calibration;  // the cameras' calibration file, absolute; empty: none given
  // As written: "~/" and the operator's data folder when empty are ResolveDatabasePath's
  // (control/database), which reads it.
  std::string database;
  std::string log_level = "info";  // under each process's own
};

// The keys every process has in its own section, processes.NAME. ParseProcessOptions reads
// them into ProcessOptions::entry (after --host, --port, --bind and --log-level).
struct ProcessEntry {
  std::string program;             // the program that runs it (igms run, igms config check)
  std::string host = "127.0.0.1";  // where the others find it
  std::optional<int> port;         // empty: the program's own default port
  std::string bind;                // the address it listens on; empty: its host
  std::string log_level;           // empty: lab.log_level
};

// The keys above, bound to `lab` and `entry`, and lab.permissions (read by SecurityOf).
Keys CommonKeys(LabOptions* lab, ProcessEntry* entry);
// The same declarations bound to nothing (for checking a file and for help).
const Keys& CommonKeys();
// `lab`'s shared keys of a lab file; throws ConfigError for a value of the wrong type.
LabOptions LabOptionsOf(const LabConfig& config);

// Every key in `lab` and in processes.NAME that `keys` does not declare, with file and line
// and, when one is close, the declared key that was likely meant.
std::vector<KeyProblem> UnknownKeys(const LabConfig& config, const std::string& name,
                                    const Keys& keys);
// Values of the wrong type or not among a key's choices. With `paths`, also every path key
// whose file does not exist.
std::vector<KeyProblem> BadValues(const LabConfig& config, const std::string& name,
                                  const Keys& keys, bool paths);

// The declared key closest to `key` (a likely typo), or "".
std::string ClosestKey(const std::string& key, const std::vector<std::string>& declared);

}  // namespace igms::config
