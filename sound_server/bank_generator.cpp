#include "sound_server/bank_generator.h"

#include <sstream>

#include "common/process/process.h"

namespace igms::sound {
namespace {

std::vector<std::string> SplitWords(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> words;
  for (std::string word; in >> word;) words.push_back(word);
  return words;
}

std::string PeakArg(double peak_db) {
  std::ostringstream out;
  out << peak_db;
  return out.str();
}

// Synthesises into a temporary file, then mixes down, resamples and normalises into `out`,
// so a half-written file never carries the final name.
std::string GenerateEntry(const Manifest& manifest, const SoundEntry& entry,
                          const std::filesystem::path& out, const GenerateOptions& options) {
  const std::filesystem::path raw = out.string() + ".raw.wav";
  const std::filesystem::path tmp = out.string() + ".tmp.wav";
  const std::string rate = std::to_string(manifest.sample_rate);
  std::vector<std::string> make;
  if (entry.kind == SoundKind::kCue) {
    make = {options.sox, "-q", "-n", "-r", rate, "-b", "16", "-c", std::to_string(entry.channels),
            raw.string()};
    for (std::string& word : SplitWords(entry.sox)) make.push_back(std::move(word));
  } else {
    make = {options.espeak, "-v",         manifest.voice, "-s", std::to_string(manifest.speed),
            "-w",           raw.string(), entry.text};
  }
  std::string error = RunProgram(make);
  if (error.empty()) {
    error = RunProgram({options.sox, "-q", raw.string(), "-r", rate, "-b", "16", "-c", "1",
                        tmp.string(), "remix", "-", "norm", PeakArg(manifest.peak_db)});
  }
  std::error_code ec;
  std::filesystem::remove(raw, ec);
  if (error.empty()) std::filesystem::rename(tmp, out, ec);
  if (error.empty() && ec) error = "cannot rename " + tmp.string() + ": " + ec.message();
  if (!error.empty()) std::filesystem::remove(tmp, ec);
  return error;
}

}  // namespace

GenerateResult GenerateBank(const Manifest& manifest, const std::filesystem::path& out_dir,
                            const GenerateOptions& options) {
  GenerateResult result;
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) {
    result.errors.push_back("cannot create " + out_dir.string() + ": " + ec.message());
    return result;
  }
  for (const SoundEntry& entry : manifest.sounds) {
    const std::filesystem::path out = out_dir / entry.file;
    std::filesystem::create_directories(out.parent_path(), ec);
    std::string error = ec ? "cannot create " + out.parent_path().string() + ": " + ec.message()
                           : GenerateEntry(manifest, entry, out, options);
    if (!error.empty()) {
      result.errors.push_back("sound " + std::to_string(entry.id) + " '" + entry.key +
                              "': " + error);
    } else {
      ++result.generated;
    }
  }
  const std::filesystem::path copy = out_dir / "manifest.yaml";
  if (std::filesystem::weakly_canonical(copy, ec) !=
      std::filesystem::weakly_canonical(manifest.path, ec)) {
    std::filesystem::copy_file(manifest.path, copy,
                               std::filesystem::copy_options::overwrite_existing, ec);
    if (ec) result.errors.push_back("cannot copy the manifest: " + ec.message());
  }
  return result;
}

}  // namespace igms::sound
