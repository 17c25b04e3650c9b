#include "device_daemons/joystick/cerealbox_protocol.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace igms::devices::cerealbox {

int Layout::analog_count() const { return std::popcount(static_cast<unsigned>(analog_mask)); }
int Layout::encoder_count() const { return std::popcount(static_cast<unsigned>(encoder_mask)); }
size_t Layout::report_length() const {
  return 2 + 2 * static_cast<size_t>(digital_banks) + 2 * static_cast<size_t>(analog_count()) +
         4 * static_cast<size_t>(encoder_count());
}

std::string IdentString(char box_type) {
  std::string s(kCopyright);
  s += " 1992 FlyBox ";  // pads to character 38
  s += "3.07";
  s += box_type;
  s += '\n';
  return s;
}

bool ParseIdent(std::string_view text, char* box_type, std::string* version) {
  if (text.size() != kIdentLength || text.substr(0, kCopyright.size()) != kCopyright) return false;
  if (text[39] != '.' || text[43] != '\n') return false;
  *version = std::string(text.substr(38, 4));
  *box_type = text[42];
  return true;
}

std::string ConfigCommand(const Layout& layout, char command) {
  std::string s(1, command);
  const auto put = [&s](unsigned v) { s.push_back(static_cast<char>(v + kOffset)); };
  put(layout.analog_mask & 0x0F);
  const unsigned banks = (1U << std::clamp(layout.digital_banks, 0, kMaxBanks)) - 1U;
  put(((layout.analog_mask >> 4) & 0x0F) | (banks << 4));
  put(0);
  put(0);
  put(layout.encoder_mask & 0x0F);
  put(layout.encoder_mask & 0x0F);
  put((layout.encoder_mask >> 4) & 0x0F);
  put((layout.encoder_mask >> 4) & 0x0F);
  s.push_back('\n');
  return s;
}

bool ParseConfig(std::string_view eight, Layout* layout) {
  if (eight.size() != 8) return false;
  unsigned v[8];
  for (int i = 0; i < 8; ++i) {
    const auto c = static_cast<uint8_t>(eight[i]);
    if (c < kOffset || c > kOffset + 0x7F - kOffset) return false;
    v[i] = c - kOffset;
  }
  if (v[0] > 0x0F || v[4] > 0x0F || v[6] > 0x0F) return false;
  layout->analog_mask = static_cast<uint8_t>(v[0] | ((v[1] & 0x0F) << 4));
  layout->digital_banks = std::popcount((v[1] >> 4) & 0x07U);
  layout->encoder_mask = static_cast<uint8_t>(v[4] | (v[6] << 4));
  return true;
}

uint16_t AnalogToRaw(double value) {
  if (!std::isfinite(value)) value = 0;
  value = std::clamp(value, -1.0, 1.0);
  return static_cast<uint16_t>(std::lround((value + 1.0) * 4095.0 / 2.0));
}

double RawToAnalog(uint16_t raw) { return -1.0 + 2.0 * raw / 4095.0; }

std::string EncodeReport(const Layout& layout, const Report& report) {
  std::string s(1, 'p');
  const auto put = [&s](unsigned v) { s.push_back(static_cast<char>((v & 0x3F) + kOffset)); };
  for (int i = 2 * layout.digital_banks - 1; i >= 0; --i) put((report.digital >> (4 * i)) & 0x0F);
  for (int i = 0; i < layout.analog_count(); ++i) {
    const uint16_t raw = AnalogToRaw(report.analog[i]);
    put(raw >> 6);
    put(raw);
  }
  for (int i = 0; i < layout.encoder_count(); ++i) {
    const auto v = static_cast<uint32_t>(report.encoders[i]) & 0xFFFFFF;
    for (int k = 0; k < 4; ++k) put(v >> (6 * k));
  }
  s.push_back('\n');
  return s;
}

ParseResult ReportParser::Feed(uint8_t byte) {
  if (byte == 'p') {
    // 'p' never occurs inside a report: a report was cut short if one was under way.
    const bool truncated = !syncing_;
    buffer_.assign(1, 'p');
    syncing_ = false;
    if (truncated) {
      ++bad_;
      return ParseResult::kBad;
    }
    return ParseResult::kNeedMore;
  }
  if (syncing_) {
    ++garbage_;
    return ParseResult::kBad;
  }
  buffer_.push_back(static_cast<char>(byte));
  const size_t length = layout_.report_length();
  if (buffer_.size() < length) {
    if (byte < kOffset || byte > kOffset + 0x3F) {  // not a value character
      ++bad_;
      syncing_ = true;
      return ParseResult::kBad;
    }
    return ParseResult::kNeedMore;
  }
  syncing_ = true;
  if (byte != '\n') {
    ++bad_;
    return ParseResult::kBad;
  }
  Decode();
  ++good_;
  return ParseResult::kGood;
}

void ReportParser::Decode() {
  size_t at = 1;
  const auto next = [this, &at] { return static_cast<uint32_t>(buffer_[at++] - kOffset) & 0x3F; };
  report_ = Report{};
  for (int i = 2 * layout_.digital_banks - 1; i >= 0; --i)
    report_.digital |= (next() & 0x0F) << (4 * i);
  report_.analog_count = layout_.analog_count();
  for (int i = 0; i < report_.analog_count; ++i) {
    const uint32_t hi = next();
    report_.raw[i] = static_cast<uint16_t>((hi << 6) | next());
    report_.analog[i] = RawToAnalog(report_.raw[i]);
  }
  report_.encoder_count = layout_.encoder_count();
  for (int i = 0; i < report_.encoder_count; ++i) {
    uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v |= next() << (6 * k);
    report_.encoders[i] =
        (v & 0x800000) ? static_cast<int32_t>(v) - 0x1000000 : static_cast<int32_t>(v);
  }
}

}  // namespace igms::devices::cerealbox
