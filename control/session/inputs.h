// Input discipline: each device's raw readings become Commands (commands.h), once and only
// when they mean it.
//
//  - Viewer buttons (table 2.1) act on a combination held `hold_ns` (100 ms), measured
//    between the readings' stamps, once per hold: passing through 01 on the way to 11 does
//    not freeze and then unfreeze, and a held combination does not repeat.
//  - FlyBox buttons and trigger (table 2.2) act on being pressed (a rising edge). The first
//    reading of a subscription is a baseline, so a button already held when the joystick
//    (re)connects does not act. The stick's axes become a PointerDrive with a dead band.
//  - Voice events act only when new: a subscriber is first sent the newest command heard
//    before it subscribed, so the filter ignores every sequence up to the count the daemon
//    reported before subscribing (VoiceFilter::Subscribed), and any sequence already seen.
//
// The time of a reading is StampTimeNs: the device's own clock where it has one, else the
// daemon's CLOCK_MONOTONIC receive time. Only differences within one stream are used.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "control/session/commands.h"
#include "igms/devices.pb.h"

namespace igms::control {

int64_t StampTimeNs(const devices::Stamp& stamp);

class ViewerButtonFilter {
 public:
  explicit ViewerButtonFilter(int64_t hold_ns = 100'000'000) : hold_ns_(hold_ns) {}

  // The buttons of one reading at its stamp time; the command when the combination has now
  // been held hold_ns, at most once per hold. A time earlier than the hold's start (a
  // restarted daemon) starts the hold again.
  std::optional<CommandKind> Feed(bool left, bool right, int64_t time_ns);
  void Reset();

 private:
  int64_t hold_ns_;
  bool have_ = false;
  int combination_ = 0;
  int64_t since_ns_ = 0;
  bool acted_ = false;
};

struct JoystickInput {
  std::vector<CommandKind> commands;  // in the order trigger, buttons 1-8
  PointerDrive drive;                 // right = y, up = twist, forward = x (table 2.2)
};

class JoystickMapper {
 public:
  // Deflections of magnitude below `dead_band` read as zero (the FlyBox's centre reads
  // 0.00024, a worn stick more).
  explicit JoystickMapper(double dead_band = 0.05) : dead_band_(dead_band) {}

  JoystickInput Feed(const devices::JoystickState& reading);
  // A new subscription: the next reading is a baseline for the buttons.
  void Reset() { have_ = false; }

 private:
  double dead_band_;
  bool have_ = false;
  uint32_t buttons_ = 0;
  bool trigger_ = false;
};

class VoiceFilter {
 public:
  // Subscribed again: readings up to `newest_sequence` (the daemon's count of readings
  // before the subscription, from its Status) are old news. Until the first call every
  // reading is ignored.
  void Subscribed(uint64_t newest_sequence);
  // The command of a new reading; nullopt for an old or repeated one, or UNSPECIFIED.
  std::optional<CommandKind> Feed(const devices::VoiceState& reading);

 private:
  bool subscribed_ = false;
  uint64_t last_sequence_ = 0;
};

}  // namespace igms::control
