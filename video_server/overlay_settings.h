// The overlay settings the video server keeps for the control client (Cooke, section 2.2.2):
// where the video sits within the graphics, and the key level above which graphics cover
// the video. They survive a restart in a small YAML file.
#pragma once

#include <mutex>
#include <optional>
#include <string>

#include "common/base/result.h"

namespace igms::video {

struct Overlay {
  // Pixel offset of the video's top-left corner within the graphics, u right, v down.
  int u_offset_px = 0;
  int v_offset_px = 0;
  // Graphics brighter than this grey level (0-255) are drawn over the video; darker
  // graphics let the video through. The thesis's setting was sixty.
  int key_level = 60;

  // True when valid (else *error says why): offsets within +-4096 px, key level in 0..255.
  bool Check(std::string* error) const;
  bool operator==(const Overlay&) const = default;
};

// Reads settings from `path`. A missing file gives the defaults (first start); a file that
// exists but does not parse or holds invalid values is an error.
Result<Overlay> LoadOverlaySettings(const std::string& path);

// Writes settings to `path` atomically (a temporary file renamed over it), so a crash never
// leaves half a file. False with `error` set when the folder is not writable.
bool SaveOverlaySettings(const std::string& path, const Overlay& settings, std::string* error);

// The settings in memory plus their file; thread-safe. An empty path keeps them in memory.
class OverlayStore {
 public:
  explicit OverlayStore(std::string path, Overlay initial = {})
      : path_(std::move(path)), settings_(initial) {}

  Overlay Get() const;
  // Validates, writes the file, then takes the new settings; on error nothing changes.
  bool Set(const Overlay& settings, std::string* error);
  const std::string& path() const { return path_; }

 private:
  const std::string path_;
  mutable std::mutex mutex_;
  Overlay settings_;
};

}  // namespace igms::video
