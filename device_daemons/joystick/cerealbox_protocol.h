// The BG Systems CerealBox serial protocol, which the FlyBox joystick speaks (Cooke,
// Interactive Graphical Model Building using Virtual Reality, section 2.1.4). Written down
// in docs/devices.md; summary:
//
//   host 'T'            box: 44-character identification, "Copyright (c), BG Systems...",
//                       EEPROM version at characters 38..41 ("3.07"), box type at 42, '\n'.
//   host 'c' or 's' + 8 configuration characters + '\n'
//                       box: "a\n". Characters are offset by 0x21: [0] analog channels 1-4
//                       (bit mask), [1] channels 5-8 in bits 0-3 and digital banks (8 inputs
//                       each) in bits 4-6, [2..3] digital outputs, [4..7] encoders 1-4 and
//                       5-8 (enable, incremental).
//   host 'p' or 'o'     box: one report. 'C': reports continuously at the box's maximum rate
//                       until any other command; 'h': handshake, the box answers "a\n" (and
//                       leaves continuous mode). Bytes that are no command are ignored.
//   report              'p', two characters per digital bank (four inputs a character, the
//                       highest nibble first), two per analog channel (12 bits, high six
//                       first), four per encoder (24 bits, low six first), '\n'. Every
//                       character between is a value plus 0x21, so none is 'p' or '\n'.
//   analog              value v in 0..4095 means -1 + 2 v / 4095.
//
// FlyBox wiring used here: analog 1-3 = stick forward/back, left/right, twist; 4-5 = the
// two levers; digital bits 0-7 = buttons 1-8, bit 8 = trigger.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "device_daemons/serial/frame7.h"  // ParseResult

namespace igms::devices::cerealbox {

inline constexpr uint8_t kOffset = 0x21;
inline constexpr size_t kIdentLength = 44;
inline constexpr std::string_view kCopyright = "Copyright (c), BG Systems";
inline constexpr int kMaxAnalog = 8;
inline constexpr int kMaxBanks = 3;
inline constexpr int kMaxEncoders = 8;
inline constexpr int kTriggerBit = 8;

// What the box reports, as set by the configuration command.
struct Layout {
  uint8_t analog_mask = 0x1F;  // FlyBox: five channels
  int digital_banks = 2;       // FlyBox: buttons 1-8 and the trigger
  uint8_t encoder_mask = 0;
  int analog_count() const;
  int encoder_count() const;
  size_t report_length() const;  // including 'p' and '\n'
};

inline constexpr Layout kFlyBoxLayout{};

struct Report {
  std::array<double, kMaxAnalog> analog{};  // in enabled-channel order, [-1, 1]
  std::array<uint16_t, kMaxAnalog> raw{};   // 0..4095
  int analog_count = 0;
  uint32_t digital = 0;  // bit i = input i
  std::array<int32_t, kMaxEncoders> encoders{};
  int encoder_count = 0;
};

// 44-character identification for a box of the given type and EEPROM version "3.07".
std::string IdentString(char box_type);
// Parses an identification. False if it is not one.
bool ParseIdent(std::string_view text, char* box_type, std::string* version);

// The 10-byte configuration command ('c' ... '\n') for a layout.
std::string ConfigCommand(const Layout& layout, char command = 'c');
// Decodes the 8 configuration characters (after 'c'/'s', before '\n'). False if malformed.
bool ParseConfig(std::string_view eight, Layout* layout);

uint16_t AnalogToRaw(double value);  // clamped to [-1, 1]
double RawToAnalog(uint16_t raw);

std::string EncodeReport(const Layout& layout, const Report& report);

// Byte-fed report parser for one layout: syncs on 'p', bounds the length, checks every
// character's range and the final '\n'.
class ReportParser {
 public:
  explicit ReportParser(Layout layout) : layout_(layout) {}
  ParseResult Feed(uint8_t byte);
  const Report& report() const { return report_; }
  const Layout& layout() const { return layout_; }
  uint64_t good_frames() const { return good_; }
  uint64_t bad_frames() const { return bad_; }
  uint64_t garbage_bytes() const { return garbage_; }

 private:
  void Decode();
  Layout layout_;
  std::string buffer_;
  bool syncing_ = true;
  Report report_;
  uint64_t good_ = 0, bad_ = 0, garbage_ = 0;
};

}  // namespace igms::devices::cerealbox
