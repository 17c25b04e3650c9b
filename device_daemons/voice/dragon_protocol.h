// The Dragon Writer's serial line (Cooke, Interactive Graphical Model Building using
// Virtual Reality, section 2.1.6, table 2.4): the speech PC sent "two ascii digits whenever
// a verbal command is recognized" at 9600 baud. The codes are command_language.h's. What
// else went over the line does not survive, so the rest is ours (docs/devices.md):
//
//   device -> host   D D CR    a recognised command, its two-digit code ("01\r" freeze)
//                    0 0 CR    "alive": the answer to a probe or a state change
//   host -> device   ? CR      probe: is the speech PC there?
//                    S d CR    the system's operator state, d = 1 verification,
//                              2 model building, 3 awaiting the object type; the
//                              recogniser's grammar follows it (the thesis's flaw fixed)
//
// A line is ended by CR (LF is also taken, and an empty line is ignored), so a receiver
// that lost its place resynchronises at the next line end: a report is the last two bytes
// before it, and whatever came before them in the line is counted as garbage. At 9600 baud
// a report is 3 bytes, 3.1 ms. A host that reads only digit pairs, as the thesis's did,
// still reads the codes.
//
// Both parsers are byte-fed, allocation-free and do no I/O: each keeps the last two bytes
// of the line, so a line of any length costs bounded memory.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "device_daemons/serial/frame7.h"
#include "device_daemons/voice/command_language.h"

namespace igms::voice::dragon {

inline constexpr char kLineEnd = '\r';
inline constexpr char kProbe = '?';
inline constexpr char kSetState = 'S';
// Probes a second while connected: the line is otherwise silent until the operator speaks,
// and the watchdog needs to hear from the device.
inline constexpr double kProbeHz = 5.0;

std::string EncodeCommand(Command command);       // "01\r"
std::string EncodeAlive();                        // "00\r"
std::string EncodeProbe();                        // "?\r"
std::string EncodeSetState(OperatorState state);  // "S2\r"
char StateDigit(OperatorState state);             // '1', '2', '3'
std::optional<OperatorState> StateFromDigit(char digit);

// What the device sent: a command, or "alive" (command unset).
struct Report {
  std::optional<Command> command;
};

// device -> host.
class ReportParser {
 public:
  // kGood: report() holds a report until the next Feed. kBad: a line ended without a
  // valid report (counted in bad_frames). Bytes pushed out of a line ahead of its last two
  // are counted in garbage_bytes as they go.
  devices::ParseResult Feed(uint8_t byte);
  const Report& report() const { return report_; }
  void Reset() { kept_ = 0; }
  uint64_t good_frames() const { return good_; }
  uint64_t bad_frames() const { return bad_; }
  uint64_t garbage_bytes() const { return garbage_; }

 private:
  uint8_t last_[2] = {0, 0};
  int kept_ = 0;
  Report report_;
  uint64_t good_ = 0, bad_ = 0, garbage_ = 0;
};

// What the host sent: a probe, or a state.
struct HostRequest {
  bool probe = false;
  std::optional<OperatorState> state;
};

// host -> device, for the simulator (and the fuzzer). Same rules as ReportParser.
class HostParser {
 public:
  devices::ParseResult Feed(uint8_t byte);
  const HostRequest& request() const { return request_; }
  uint64_t bad_frames() const { return bad_; }
  uint64_t garbage_bytes() const { return garbage_; }

 private:
  uint8_t last_[2] = {0, 0};
  int kept_ = 0;
  HostRequest request_;
  uint64_t bad_ = 0, garbage_ = 0;
};

}  // namespace igms::voice::dragon
