#include "video_server/capture_registry.h"

#include <map>

namespace igms::video {
namespace {

std::map<std::string, CaptureBackendFactory>& Registry() {
  static std::map<std::string, CaptureBackendFactory> registry;
  return registry;
}

}  // namespace

void RegisterCaptureBackend(const std::string& name, CaptureBackendFactory factory) {
  Registry()[name] = std::move(factory);
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
