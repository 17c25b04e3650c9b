// Between the voice library's enums and the devices protocol's (proto/igms/devices.proto):
// a VoiceCommand's number is the command's two-digit code; OperatorState maps one to one.
#pragma once

#include <optional>
#include <string>

#include "device_daemons/voice/command_language.h"
#include "igms/devices.pb.h"

namespace igms::voice {

inline devices::VoiceCommand ToProto(Command command) {
  return static_cast<devices::VoiceCommand>(std::stoi(std::string(Code(command))));
}

inline devices::OperatorState ToProto(OperatorState state) {
  switch (state) {
    case OperatorState::kVerification:
      return devices::VERIFICATION;
    case OperatorState::kModelBuilding:
      return devices::MODEL_BUILDING;
    case OperatorState::kAwaitingType:
      return devices::AWAITING_OBJECT_TYPE;
  }
  return devices::OPERATOR_STATE_UNSPECIFIED;
}

// nullopt for OPERATOR_STATE_UNSPECIFIED and unknown numbers.
inline std::optional<OperatorState> FromProto(devices::OperatorState state) {
  switch (state) {
    case devices::VERIFICATION:
      return OperatorState::kVerification;
    case devices::MODEL_BUILDING:
      return OperatorState::kModelBuilding;
    case devices::AWAITING_OBJECT_TYPE:
      return OperatorState::kAwaitingType;
    default:
      return std::nullopt;
  }
}

// nullopt for VOICE_COMMAND_UNSPECIFIED and unknown numbers.
inline std::optional<Command> FromProto(devices::VoiceCommand command) {
  const int n = static_cast<int>(command);
  if (n <= 0 || n > 99) return std::nullopt;
  const char code[2] = {static_cast<char>('0' + n / 10), static_cast<char>('0' + n % 10)};
  return CommandFromCode(std::string_view(code, 2));
}

}  // namespace igms::voice
