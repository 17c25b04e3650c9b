// The sound server's tests and benchmark: where the generated bank is, and a scratch copy
// of it with extra entries whose files are missing or corrupt.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/files.h"

namespace igms::sound::testing {

inline std::filesystem::path BuildDir() {
  const char* dir = std::getenv("IGMS_BUILD_DIR");
  return dir != nullptr ? dir : ".";
}

inline std::filesystem::path BankDir() { return BuildDir() / "share/igms/sounds"; }

// The lab bank plus sound 900 'missing_file' (no file) and 901 'corrupt_file' (garbage
// bytes), in a new folder; returns its manifest.
inline std::filesystem::path DamagedBank(const std::filesystem::path& dir) {
  std::filesystem::create_directory_symlink(BankDir() / "cues", dir / "cues");
  std::filesystem::create_directory_symlink(BankDir() / "speech", dir / "speech");
  std::filesystem::create_directories(dir / "extra");
  std::ofstream(dir / "extra/corrupt.wav") << "RIFF this is not audio at all";
  std::ifstream lab(BankDir() / "manifest.yaml");
  std::ofstream manifest(dir / "manifest.yaml");
  manifest << lab.rdbuf()
           << "\n  - {id: 900, key: missing_file, kind: cue, sox: \"synth 0.1 sine 440\", "
              "file: extra/missing.wav}\n"
           << "  - {id: 901, key: corrupt_file, kind: cue, sox: \"synth 0.1 sine 440\", "
              "file: extra/corrupt.wav}\n";
  return dir / "manifest.yaml";
}

}  // namespace igms::sound::testing
