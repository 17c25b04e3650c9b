#include "device_daemons/voice/command_language.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <stdexcept>

namespace igms::voice {
namespace {

constexpr std::array<CommandInfo, 11> kCommands = {{
    {Command::kFreeze, "01", "freeze"},
    {Command::kRange, "02", "range"},
    {Command::kUnfreeze, "03", "unfreeze"},
    {Command::kBox, "10", "box"},
    {Command::kCylinder, "11", "cylinder"},
    {Command::kMark, "20", "mark"},
    {Command::kUnmark, "21", "unmark"},
    {Command::kRemovePoints, "22", "remove points"},
    {Command::kWireframe, "30", "wireframe"},
    {Command::kSolid, "31", "solid"},
    {Command::kRemoveModel, "32", "remove model"},
}};

constexpr std::array<OperatorState, 3> kStates = {
    OperatorState::kVerification, OperatorState::kModelBuilding, OperatorState::kAwaitingType};

constexpr std::array<Command, 4> kVerification = {Command::kFreeze, Command::kWireframe,
                                                  Command::kSolid, Command::kRemoveModel};
constexpr std::array<Command, 8> kModelBuilding = {
    Command::kRange,        Command::kUnfreeze,  Command::kMark,  Command::kUnmark,
    Command::kRemovePoints, Command::kWireframe, Command::kSolid, Command::kRemoveModel};
constexpr std::array<Command, 5> kAwaitingType = {Command::kUnfreeze, Command::kBox,
                                                  Command::kCylinder, Command::kUnmark,
                                                  Command::kRemovePoints};

// Lower case with runs of white space collapsed to one space and the ends trimmed.
std::string Normalise(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (std::isspace(static_cast<unsigned char>(c))) {
      if (!out.empty() && out.back() != ' ') out.push_back(' ');
    } else {
      out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
    }
  }
  if (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

}  // namespace

std::span<const CommandInfo> AllCommands() { return kCommands; }

const CommandInfo& Info(Command command) {
  for (const CommandInfo& info : kCommands) {
    if (info.command == command) return info;
  }
  throw std::logic_error("voice: command missing from the command table");
}

std::string_view Code(Command command) { return Info(command).code; }
std::string_view Phrase(Command command) { return Info(command).phrase; }

std::optional<Command> CommandFromCode(std::string_view code) {
  for (const CommandInfo& info : kCommands) {
    if (info.code == code) return info.command;
  }
  return std::nullopt;
}

std::optional<Command> CommandFromPhrase(std::string_view text) {
  const std::string normal = Normalise(text);
  for (const CommandInfo& info : kCommands) {
    if (info.phrase == normal) return info.command;
  }
  return std::nullopt;
}

std::span<const OperatorState> AllStates() { return kStates; }

std::string_view StateName(OperatorState state) {
  switch (state) {
    case OperatorState::kVerification:
      return "verification";
    case OperatorState::kModelBuilding:
      return "model_building";
    case OperatorState::kAwaitingType:
      return "awaiting_type";
  }
  throw std::logic_error("voice: unknown operator state");
}

std::optional<OperatorState> StateFromName(std::string_view name) {
  const std::string normal = Normalise(name);
  for (OperatorState state : kStates) {
    if (StateName(state) == normal) return state;
  }
  if (normal == "building") return OperatorState::kModelBuilding;
  if (normal == "type") return OperatorState::kAwaitingType;
  return std::nullopt;
}

std::span<const Command> ValidCommands(OperatorState state) {
  switch (state) {
    case OperatorState::kVerification:
      return kVerification;
    case OperatorState::kModelBuilding:
      return kModelBuilding;
    case OperatorState::kAwaitingType:
      return kAwaitingType;
  }
  throw std::logic_error("voice: unknown operator state");
}

bool IsValid(OperatorState state, Command command) {
  const auto valid = ValidCommands(state);
  return std::find(valid.begin(), valid.end(), command) != valid.end();
}

OperatorState PredictNextState(OperatorState state, Command command) {
  if (!IsValid(state, command)) return state;
  switch (command) {
    case Command::kFreeze:
    case Command::kBox:
    case Command::kCylinder:
      return OperatorState::kModelBuilding;
    case Command::kUnfreeze:
      return OperatorState::kVerification;
    case Command::kUnmark:
    case Command::kRemovePoints:
      return state == OperatorState::kAwaitingType ? OperatorState::kModelBuilding : state;
    default:
      return state;
  }
}

}  // namespace igms::voice
