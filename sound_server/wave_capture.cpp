#include "sound_server/wave_capture.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

namespace igms::sound {
namespace {

uint32_t Le32(const char* p) {
  return uint32_t(uint8_t(p[0])) | uint32_t(uint8_t(p[1])) << 8 | uint32_t(uint8_t(p[2])) << 16 |
         uint32_t(uint8_t(p[3])) << 24;
}
uint16_t Le16(const char* p) { return uint16_t(uint8_t(p[0]) | uint8_t(p[1]) << 8); }

struct Layout {
  int sample_rate = 0;
  int channels = 0;
  int bits = 0;
  int64_t data_offset = -1;
};

// Walks the RIFF chunks up to "data"; the data chunk's size is not trusted.
std::optional<Layout> ReadLayout(std::ifstream& in) {
  char head[12];
  if (!in.read(head, 12) || std::memcmp(head, "RIFF", 4) != 0 ||
      std::memcmp(head + 8, "WAVE", 4) != 0) {
    return std::nullopt;
  }
  Layout layout;
  char chunk[8];
  while (in.read(chunk, 8)) {
    const uint32_t size = Le32(chunk + 4);
    if (std::memcmp(chunk, "data", 4) == 0) {
      layout.data_offset = in.tellg();
      break;
    }
    if (std::memcmp(chunk, "fmt ", 4) == 0 && size >= 16 && size < 1024) {
      std::string fmt(size, '\0');
      if (!in.read(fmt.data(), size)) return std::nullopt;
      layout.channels = Le16(fmt.data() + 2);
      layout.sample_rate = static_cast<int>(Le32(fmt.data() + 4));
      layout.bits = Le16(fmt.data() + 14);
    } else {
      in.seekg(size + (size & 1), std::ios::cur);
    }
  }
  if (layout.data_offset < 0 || layout.channels != 1 || layout.bits != 16) return std::nullopt;
  return layout;
}

}  // namespace

std::optional<Capture> ReadCapture(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  const std::optional<Layout> layout = ReadLayout(in);
  if (!layout) return std::nullopt;
  std::error_code ec;
  const int64_t bytes = static_cast<int64_t>(std::filesystem::file_size(path, ec));
  if (ec) return std::nullopt;
  Capture capture;
  capture.sample_rate = layout->sample_rate;
  capture.samples.resize(
      static_cast<size_t>(std::max<int64_t>(0, bytes - layout->data_offset) / 2));
  in.clear();
  in.seekg(layout->data_offset);
  in.read(reinterpret_cast<char*>(capture.samples.data()),
          static_cast<std::streamsize>(capture.samples.size() * 2));
  capture.samples.resize(static_cast<size_t>(in.gcount() / 2));
  return capture;
}

int64_t CapturedFrames(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return -1;
  const std::optional<Layout> layout = ReadLayout(in);
  if (!layout) return -1;
  std::error_code ec;
  const auto bytes = static_cast<int64_t>(std::filesystem::file_size(path, ec));
  return ec ? -1 : std::max<int64_t>(0, bytes - layout->data_offset) / 2;
}

Alignment AlignClip(const std::vector<int16_t>& signal, const std::vector<int16_t>& clip,
                    int64_t from, int64_t to, size_t window) {
  Alignment best;
  const size_t n = std::min(window, clip.size());
  if (n == 0) return best;
  double clip_energy = 0.0;
  for (size_t i = 0; i < n; ++i) clip_energy += double(clip[i]) * clip[i];
  from = std::max<int64_t>(from, 0);
  to = std::min<int64_t>(to, static_cast<int64_t>(signal.size()) - static_cast<int64_t>(n) + 1);
  for (int64_t o = from; o < to; ++o) {
    double dot = 0.0, energy = 0.0;
    for (size_t i = 0; i < n; ++i) {
      const double s = signal[static_cast<size_t>(o) + i];
      dot += s * clip[i];
      energy += s * s;
    }
    const double c = (energy > 0 && clip_energy > 0) ? dot / std::sqrt(energy * clip_energy) : 0;
    if (c > best.correlation) best = {o, c};
  }
  return best;
}

std::vector<double> Subtract(const std::vector<double>& signal, const std::vector<int16_t>& clip,
                             int64_t offset, double gain) {
  std::vector<double> out = signal;
  for (size_t i = 0; i < clip.size(); ++i) {
    const int64_t at = offset + static_cast<int64_t>(i);
    if (at >= 0 && at < static_cast<int64_t>(out.size()))
      out[static_cast<size_t>(at)] -= gain * clip[i];
  }
  return out;
}

double RmsOf(const std::vector<double>& signal, size_t begin, size_t end) {
  end = std::min(end, signal.size());
  if (begin >= end) return 0.0;
  double sum = 0.0;
  for (size_t i = begin; i < end; ++i) sum += signal[i] * signal[i];
  return std::sqrt(sum / double(end - begin)) / 32768.0;
}

}  // namespace igms::sound
