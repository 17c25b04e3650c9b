#include "common/config/lab_config.h"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace igms::config {

namespace {

std::vector<std::string> SplitKey(const std::string& key) {
  std::vector<std::string> parts;
  std::stringstream ss(key);
  std::string part;
  while (std::getline(ss, part, '.')) {
    if (!part.empty()) parts.push_back(part);
  }
  return parts;
}

}  // namespace

LabConfig::LabConfig() : root_(std::in_place, YAML::NodeType::Map), source_("<defaults>") {}

LabConfig::LabConfig(const LabConfig& other)
    : root_(YAML::Clone(*other.root_)), source_(other.source_), folder_(other.folder_) {}

// The moves rebind through std::optional (a Node's copy constructor rebinds and cannot fail)
// rather than Node::reset, which checks that both nodes are valid and may throw.
LabConfig::LabConfig(LabConfig&& other) noexcept
    : root_(std::move(other.root_)),
      source_(std::move(other.source_)),
      folder_(std::move(other.folder_)) {
  other.root_.emplace(YAML::NodeType::Map);  // no alias left behind
}

LabConfig& LabConfig::operator=(const LabConfig& other) {
  if (this == &other) return *this;
  // emplace() rebinds; Node's operator= would write other's tree into the one root_ shares.
  root_.emplace(YAML::Clone(*other.root_));
  source_ = other.source_;
  folder_ = other.folder_;
  return *this;
}

LabConfig& LabConfig::operator=(LabConfig&& other) noexcept {
  if (this == &other) return *this;
  root_.emplace(*other.root_);
  other.root_.emplace(YAML::NodeType::Map);
  source_ = std::move(other.source_);
  folder_ = std::move(other.folder_);
  return *this;
}

LabConfig LabConfig::Load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot open the lab configuration file");
  std::stringstream text;
  text << in.rdbuf();
  LabConfig config = FromString(text.str(), path);
  config.folder_ = std::filesystem::absolute(path).parent_path().string();
  return config;
}

LabConfig LabConfig::FromString(const std::string& text, const std::string& source) {
  LabConfig config;
  config.source_ = source;
  config.folder_ = std::filesystem::current_path().string();
  try {
    YAML::Node root = YAML::Load(text);
    if (root.IsNull() || !root.IsDefined()) root = YAML::Node(YAML::NodeType::Map);
    if (!root.IsMap()) {
      throw ConfigError(source + ":" + std::to_string(root.Mark().line + 1) +
                        ": the lab configuration must be a map of keys");
    }
    config.root_.emplace(root);
  } catch (const YAML::Exception& e) {
    throw ConfigError(source + ":" + std::to_string(e.mark.line + 1) + ":" +
                      std::to_string(e.mark.column + 1) + ": " + e.msg);
  }
  return config;
}

YAML::Node LabConfig::Find(const std::string& key) const {
  // YAML::Node assignment rebinds in yaml-cpp only through reset(); walk with copies.
  YAML::Node node;
  node.reset(*root_);
  for (const auto& part : SplitKey(key)) {
    if (!node.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    YAML::Node child = node[part];
    if (!child.IsDefined()) return YAML::Node(YAML::NodeType::Undefined);
    node.reset(child);
  }
  return node;
}

bool LabConfig::Has(const std::string& key) const {
  const YAML::Node n = Find(key);
  return n.IsDefined() && !n.IsNull();
}

void LabConfig::Set(const std::string& key, const std::string& value) {
  const auto parts = SplitKey(key);
  if (parts.empty()) throw ConfigError("cannot set an empty key");
  YAML::Node parsed;
  try {
    parsed = YAML::Load(value);
  } catch (const YAML::Exception& e) {
    throw ConfigError("--set " + key + "=" + value + ": " + e.msg);
  }
  YAML::Node node;
  node.reset(*root_);
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node child = node[parts[i]];
    if (!child.IsDefined() || !child.IsMap()) {
      node[parts[i]] = YAML::Node(YAML::NodeType::Map);
      child.reset(node[parts[i]]);
    }
    node.reset(child);
  }
  node[parts.back()] = parsed;
}

std::vector<std::string> LabConfig::ProcessNames() const {
  std::vector<std::string> names;
  const YAML::Node processes = Find("processes");
  if (processes.IsMap()) {
    for (const auto& kv : processes) names.push_back(kv.first.as<std::string>());
  }
  return names;
}

std::string LabConfig::ResolvePath(const std::string& path) const {
  if (path.empty() || std::filesystem::path(path).is_absolute()) return path;
  return (std::filesystem::path(folder_) / path).lexically_normal().string();
}

std::string LabConfig::Dump() const {
  YAML::Emitter out;
  out << *root_;
  return out.c_str();
}

std::string LabConfig::Text(const YAML::Node& node) {
  if (node.IsScalar()) return node.Scalar();
  YAML::Emitter out;
  out << YAML::Flow << node;
  return out.c_str();
}

ConfigError LabConfig::Error(const std::string& key, const YAML::Node& node,
                             const std::string& what) const {
  std::string where = source_;
  if (node.IsDefined() && node.Mark().line >= 0) {
    where += ":" + std::to_string(node.Mark().line + 1);
  }
  return ConfigError(where + ": " + key + " " + what);
}

}  // namespace igms::config
