// The lab configuration: one YAML file for the whole lab (docs/configuration.md).
//
//   lab:            # what every process shares
//     token: ""     # optional shared secret; when set, every client must present it
//     calibration: calibration.yaml
//     database: igms.db
//   processes:      # one entry per process, named by --name
//     video:
//       program: igms-video-server
//       host: 127.0.0.1   # where it listens and where clients find it
//       port: 7301
//       ...               # the component's own section
//
// Keys are addressed with dots ("processes.video.port"). Every error names the file, the line
// and the key ("lab.yaml:12: processes.video.port: expected an integer, found 'abc'").
// Relative paths in the file are relative to the file's folder (ResolvePath).
#pragma once

#include <yaml-cpp/yaml.h>

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace igms::config {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class LabConfig {
 public:
  LabConfig();  // empty: every Get with a fallback returns it
  // A copy is a file of its own: yaml-cpp's Node copies share one tree, and assigning one
  // Node to another rewrites the tree it shared, so a copy's Set (or an assignment to a
  // copy) would change the original. Copies clone the tree; moves take it over.
  LabConfig(const LabConfig& other);
  LabConfig(LabConfig&& other) noexcept;
  LabConfig& operator=(const LabConfig& other);
  LabConfig& operator=(LabConfig&& other) noexcept;
  ~LabConfig() = default;
  // Throws ConfigError for a missing file or bad YAML, naming the file and line.
  static LabConfig Load(const std::string& path);
  static LabConfig FromString(const std::string& text, const std::string& source = "<string>");

  bool Has(const std::string& key) const;
  // The node at key, or an undefined node.
  YAML::Node Find(const std::string& key) const;

  // Throws ConfigError when the key is missing or not a T.
  template <class T>
  T Get(const std::string& key) const {
    const YAML::Node node = Find(key);
    if (!node.IsDefined() || node.IsNull()) throw Error(key, node, "is missing");
    return Convert<T>(key, node);
  }
  // The fallback when the key is missing; throws ConfigError when present but not a T.
  template <class T>
  T Get(const std::string& key, const T& fallback) const {
    const YAML::Node node = Find(key);
    if (!node.IsDefined() || node.IsNull()) return fallback;
    return Convert<T>(key, node);
  }

  // Overrides a key (command-line flags). The value is read as YAML ("7301", "[1, 2]").
  void Set(const std::string& key, const std::string& value);
  // The names under "processes".
  std::vector<std::string> ProcessNames() const;
  // A path from the file, made absolute against the file's folder.
  std::string ResolvePath(const std::string& path) const;
  const std::string& source() const { return source_; }
  std::string Dump() const;

  // "lab.yaml:12: processes.video.port: <what>"
  ConfigError Error(const std::string& key, const YAML::Node& node, const std::string& what) const;

 private:
  template <class T>
  T Convert(const std::string& key, const YAML::Node& node) const {
    try {
      return node.as<T>();
    } catch (const YAML::Exception&) {
      throw Error(key, node,
                  "cannot be read as " + TypeName<T>() + " (found '" + Text(node) + "')");
    }
  }
  template <class T>
  static std::string TypeName();
  static std::string Text(const YAML::Node& node);

  // Always engaged; an optional so that a move can rebind it without Node::reset (which may
  // throw) and without Node's operator= (which writes into the shared tree).
  std::optional<YAML::Node> root_;
  std::string source_;
  std::string folder_;
};

template <class T>
std::string LabConfig::TypeName() {
  if constexpr (std::is_same_v<T, bool>)
    return "true or false";
  else if constexpr (std::is_integral_v<T>)
    return "an integer";
  else if constexpr (std::is_floating_point_v<T>)
    return "a number";
  else if constexpr (std::is_same_v<T, std::string>)
    return "a string";
  else
    return "the expected type";
}

}  // namespace igms::config
