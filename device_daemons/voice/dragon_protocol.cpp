#include "device_daemons/voice/dragon_protocol.h"

namespace igms::voice::dragon {
namespace {

bool IsLineEnd(uint8_t byte) { return byte == '\r' || byte == '\n'; }

// Keeps the last two bytes of a line; the one pushed out is garbage.
void Keep(uint8_t byte, uint8_t (&last)[2], int& kept, uint64_t& garbage) {
  if (kept == 2) {
    ++garbage;
    last[0] = last[1];
    last[1] = byte;
  } else {
    last[kept++] = byte;
  }
}

}  // namespace

std::string EncodeCommand(Command command) { return std::string(Code(command)) + kLineEnd; }
std::string EncodeAlive() { return std::string("00") + kLineEnd; }
std::string EncodeProbe() { return std::string(1, kProbe) + kLineEnd; }
std::string EncodeSetState(OperatorState state) {
  return std::string{kSetState, StateDigit(state), kLineEnd};
}

char StateDigit(OperatorState state) {
  switch (state) {
    case OperatorState::kVerification:
      return '1';
    case OperatorState::kModelBuilding:
      return '2';
    case OperatorState::kAwaitingType:
      return '3';
  }
  return '1';
}

std::optional<OperatorState> StateFromDigit(char digit) {
  switch (digit) {
    case '1':
      return OperatorState::kVerification;
    case '2':
      return OperatorState::kModelBuilding;
    case '3':
      return OperatorState::kAwaitingType;
    default:
      return std::nullopt;
  }
}

devices::ParseResult ReportParser::Feed(uint8_t byte) {
  if (!IsLineEnd(byte)) {
    Keep(byte, last_, kept_, garbage_);
    return devices::ParseResult::kNeedMore;
  }
  const int kept = kept_;
  kept_ = 0;
  if (kept == 0) return devices::ParseResult::kNeedMore;  // LF after CR, or a blank line
  if (kept == 2) {
    const std::string_view code(reinterpret_cast<const char*>(last_), 2);
    if (code == "00") {
      report_.command.reset();
      ++good_;
      return devices::ParseResult::kGood;
    }
    if (auto command = CommandFromCode(code)) {
      report_.command = command;
      ++good_;
      return devices::ParseResult::kGood;
    }
  }
  ++bad_;
  return devices::ParseResult::kBad;
}

devices::ParseResult HostParser::Feed(uint8_t byte) {
  if (!IsLineEnd(byte)) {
    Keep(byte, last_, kept_, garbage_);
    return devices::ParseResult::kNeedMore;
  }
  const int kept = kept_;
  kept_ = 0;
  if (kept == 0) return devices::ParseResult::kNeedMore;
  request_ = HostRequest();
  // A probe is "?" alone at the end of its line; a state is "S" and a digit.
  if (last_[kept - 1] == kProbe) {
    request_.probe = true;
    if (kept == 2) ++garbage_;
    return devices::ParseResult::kGood;
  }
  if (kept == 2 && last_[0] == kSetState) {
    if (auto state = StateFromDigit(static_cast<char>(last_[1]))) {
      request_.state = state;
      return devices::ParseResult::kGood;
    }
  }
  ++bad_;
  return devices::ParseResult::kBad;
}

}  // namespace igms::voice::dragon
