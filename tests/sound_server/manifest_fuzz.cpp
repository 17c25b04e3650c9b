// libFuzzer target: any bytes as a sound manifest give a manifest or an error, never a crash.
#include <cstddef>
#include <cstdint>
#include <string>

#include "sound_server/manifest.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const igms::Result<igms::sound::Manifest> r = igms::sound::ParseManifest(text, "fuzz.yaml");
  if (!r.ok() && r.error().empty()) __builtin_trap();
  return 0;
}
