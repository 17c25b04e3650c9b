#include "video_server/capture_registry.h"

#include <map>

namespace igms::video {
namespace {

std::map<std::string, CaptureBackendFactory>& Registry() {
  static std::map<std::string, CaptureBackendFactory> registry;
  return registry;
}

std::map<std::string, config::Keys>& KeysRegistry() {
  static std::map<std::string, config::Keys> keys;
  return keys;
}

}  // namespace

void RegisterCaptureBackend(const std::string& name, CaptureBackendFactory factory,
                            const config::Keys& keys) {
  Registry()[name] = std::move(factory);
  // Declarations only: the factory reads its keys itself, so no binding is kept.
  config::Keys declared;
  for (const auto& spec : keys.specs()) {
    declared.Add(spec.key, spec.type, spec.default_value, spec.help);
  }
  KeysRegistry()[name] = std::move(declared);
}

config::Keys CaptureBackendKeys() {
  config::Keys keys;
  for (const auto& [name, backend_keys] : KeysRegistry()) keys.Merge(backend_keys);
  return keys;
}

const CaptureBackendFactory* FindCaptureBackend(const std::string& name) {
  const auto it = Registry().find(name);
  return it == Registry().end() ? nullptr : &it->second;
}

std::vector<std::string> CaptureBackendNames() {
  std::vector<std::string> names = {"files", "camera"};
  for (const auto& [name, factory] : Registry()) {
    if (name != "files" && name != "camera") names.push_back(name);
  }
  return names;
}

}  // namespace igms::video
