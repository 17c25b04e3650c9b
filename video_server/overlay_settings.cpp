#include "video_server/overlay_settings.h"

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace igms::video {

bool Overlay::Check(std::string* error) const {
  if (u_offset_px < -4096 || u_offset_px > 4096 || v_offset_px < -4096 || v_offset_px > 4096) {
    *error = "overlay offsets must be within +-4096 pixels";
    return false;
  }
  if (key_level < 0 || key_level > 255) {
    *error = "the key level must be in 0..255";
    return false;
  }
  return true;
}

Result<Overlay> LoadOverlaySettings(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return Overlay{};
  Overlay settings;
  try {
    const YAML::Node root = YAML::LoadFile(path);
    if (!root.IsMap()) throw YAML::Exception(YAML::Mark::null_mark(), "not a map");
    settings.u_offset_px = root["u_offset_px"].as<int>(settings.u_offset_px);
    settings.v_offset_px = root["v_offset_px"].as<int>(settings.v_offset_px);
    settings.key_level = root["key_level"].as<int>(settings.key_level);
  } catch (const YAML::Exception& e) {
    return ErrorMessage{"overlay settings file " + path + " does not parse: " + e.what()};
  }
  if (std::string problem; !settings.Check(&problem)) {
    return ErrorMessage{"overlay settings file " + path + ": " + problem};
  }
  return settings;
}

bool SaveOverlaySettings(const std::string& path, const Overlay& settings, std::string* error) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::trunc);
    out << "# IGMS video server overlay settings (written by the server)\n"
        << "u_offset_px: " << settings.u_offset_px << "\n"
        << "v_offset_px: " << settings.v_offset_px << "\n"
        << "key_level: " << settings.key_level << "\n";
    out.flush();
    if (!out) {
      if (error) *error = "cannot write overlay settings file " + temporary;
      std::remove(temporary.c_str());
      return false;
    }
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    if (error) *error = "cannot replace overlay settings file " + path + ": " + ec.message();
    std::remove(temporary.c_str());
    return false;
  }
  return true;
}

Overlay OverlayStore::Get() const {
  std::lock_guard lock(mutex_);
  return settings_;
}

bool OverlayStore::Set(const Overlay& settings, std::string* error) {
  if (std::string problem; !settings.Check(&problem)) {
    if (error) *error = problem;
    return false;
  }
  std::lock_guard lock(mutex_);
  if (!path_.empty() && !SaveOverlaySettings(path_, settings, error)) return false;
  settings_ = settings;
  return true;
}

}  // namespace igms::video
