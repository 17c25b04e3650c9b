#include "sound_server/manifest.h"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <set>
#include <sstream>

namespace igms::sound {
namespace {

bool ValidKey(const std::string& key) {
  if (key.empty() || key.size() > 64) return false;
  for (char c : key) {
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) return false;
  }
  return true;
}

// Reads an optional scalar; a present value of the wrong type is an error.
template <class T>
bool ReadOptional(const YAML::Node& node, const char* name, T& out, std::string& error) {
  const YAML::Node value = node[name];
  if (!value) return true;
  try {
    out = value.as<T>();
    return true;
  } catch (const YAML::Exception&) {
    error = std::string("field '") + name + "' has the wrong type";
    return false;
  }
}

std::optional<SoundEntry> ParseEntry(const YAML::Node& node, std::string& error) {
  if (!node.IsMap()) {
    error = "is not a map";
    return std::nullopt;
  }
  SoundEntry entry;
  std::string kind;
  int64_t id = 0;
  if (!node["id"] || !node["key"] || !node["kind"]) {
    error = "needs 'id', 'key' and 'kind'";
    return std::nullopt;
  }
  if (!ReadOptional(node, "id", id, error) || !ReadOptional(node, "key", entry.key, error) ||
      !ReadOptional(node, "kind", kind, error) || !ReadOptional(node, "file", entry.file, error) ||
      !ReadOptional(node, "text", entry.text, error) ||
      !ReadOptional(node, "sox", entry.sox, error) ||
      !ReadOptional(node, "channels", entry.channels, error) ||
      !ReadOptional(node, "meaning", entry.meaning, error) ||
      !ReadOptional(node, "reason", entry.reason, error)) {
    return std::nullopt;
  }
  if (id <= 0 || id > UINT32_MAX) {
    error = "'id' must be a positive number";
    return std::nullopt;
  }
  entry.id = static_cast<uint32_t>(id);
  if (!ValidKey(entry.key)) {
    error = "'key' must be 1-64 characters of a-z, 0-9 and '_'";
    return std::nullopt;
  }
  if (kind == "cue") {
    entry.kind = SoundKind::kCue;
    if (entry.sox.empty()) error = "a cue needs 'sox' (the effects that synthesise it)";
    if (entry.channels < 1 || entry.channels > 16) error = "'channels' must be 1-16";
  } else if (kind == "speech") {
    entry.kind = SoundKind::kSpeech;
    if (entry.text.empty()) error = "a speech entry needs 'text'";
  } else {
    error = "'kind' must be 'cue' or 'speech', not '" + kind + "'";
  }
  if (!error.empty()) return std::nullopt;
  if (entry.file.empty()) {
    entry.file =
        std::string(entry.kind == SoundKind::kCue ? "cues/" : "speech/") + entry.key + ".wav";
  }
  const std::filesystem::path file(entry.file);
  if (file.is_absolute() || file.lexically_normal().string().starts_with("..")) {
    error = "'file' must stay inside the bank's folder";
    return std::nullopt;
  }
  return entry;
}

}  // namespace

const char* KindName(SoundKind kind) { return kind == SoundKind::kCue ? "cue" : "speech"; }

const SoundEntry* Manifest::FindId(uint32_t id) const {
  for (const SoundEntry& entry : sounds) {
    if (entry.id == id) return &entry;
  }
  return nullptr;
}

const SoundEntry* Manifest::FindKey(const std::string& key) const {
  for (const SoundEntry& entry : sounds) {
    if (entry.key == key) return &entry;
  }
  return nullptr;
}

Result<Manifest> ParseManifest(const std::string& text, const std::filesystem::path& path) {
  const std::string where = "sound manifest " + path.string();
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    return ErrorMessage{where + ": not valid YAML: " + e.what()};
  }
  if (!root.IsMap()) return ErrorMessage{where + ": expected a map at the top"};
  Manifest manifest;
  manifest.path = path;
  int format = 0;
  std::string error;
  if (!ReadOptional(root, "format", format, error) ||
      !ReadOptional(root, "sample_rate", manifest.sample_rate, error) ||
      !ReadOptional(root, "peak_db", manifest.peak_db, error) ||
      !ReadOptional(root, "voice", manifest.voice, error) ||
      !ReadOptional(root, "speed", manifest.speed, error)) {
    return ErrorMessage{where + ": " + error};
  }
  if (format != 1) return ErrorMessage{where + ": 'format' must be 1"};
  if (manifest.sample_rate < 8000 || manifest.sample_rate > 192000) {
    return ErrorMessage{where + ": 'sample_rate' must be 8000-192000"};
  }
  const YAML::Node sounds = root["sounds"];
  if (!sounds || !sounds.IsSequence() || sounds.size() == 0) {
    return ErrorMessage{where + ": 'sounds' must be a non-empty list"};
  }
  std::set<uint32_t> ids;
  std::set<std::string> keys;
  for (size_t i = 0; i < sounds.size(); ++i) {
    std::optional<SoundEntry> entry = ParseEntry(sounds[i], error);
    std::ostringstream name;
    name << where << ": sound #" << (i + 1);
    if (!entry) return ErrorMessage{name.str() + " " + error};
    if (!ids.insert(entry->id).second) {
      return ErrorMessage{name.str() + " repeats id " + std::to_string(entry->id)};
    }
    if (!keys.insert(entry->key).second) {
      return ErrorMessage{name.str() + " repeats key '" + entry->key + "'"};
    }
    manifest.sounds.push_back(std::move(*entry));
  }
  return manifest;
}

Result<Manifest> LoadManifest(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) return ErrorMessage{"sound manifest " + path.string() + ": cannot be read"};
  std::stringstream text;
  text << in.rdbuf();
  return ParseManifest(text.str(), path);
}

}  // namespace igms::sound
