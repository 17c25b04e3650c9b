// The spoken command language of IGMS and its finite state machine.
//
// The thesis's recogniser (Cooke, "Interactive Graphical Model Building using Virtual
// Reality", section 2.1.6, table 2.4, figure 2-3) sent two ASCII digits over a 9600-baud
// serial line for each recognised command, and used a finite state machine over the
// language so that only the words valid in the current state could be recognised. The
// codes of table 2.4 are kept; the thesis's section 2.4 names more commands (mark, unmark,
// wireframe) and table 2.6 more actions (removing points, removing a model), which get new
// codes here:
//
//   code  phrase          meaning (the control client maps it; see docs/voice.md)
//   01    freeze          enter model building (thesis)
//   02    range           move the pointer to the ultrasonic depth (thesis)
//   03    unfreeze        back to verification (thesis)
//   10    box             the object is a box (thesis)
//   11    cylinder        the object is a cylinder (thesis)
//   20    mark            place a mark at the pointer
//   21    unmark          remove the last mark
//   22    remove points   remove every mark
//   30    wireframe       draw models as wireframes
//   31    solid           draw models solid
//   32    remove model    remove the last model built
//
// The first digit groups the codes: 0x mode and pointer, 1x object types, 2x marks,
// 3x display and models. They equal the numbers of igms.devices.VoiceCommand.
//
// States (figure 2-3 rebuilt from sections 2.1.6 and 2.4):
//   verification    freeze, wireframe, solid, remove model
//   model building  unfreeze, range, mark, unmark, remove points, wireframe, solid,
//                   remove model
//   awaiting type   box, cylinder, unmark, remove points, unfreeze
// The thesis's flaw was that the recogniser advanced its state only on its own words, so
// a button press left it behind. Here the control client tells the recogniser the system's
// state whenever it changes (SetState); the recogniser only predicts the obvious next
// state after its own word (PredictNextState) until the control client says otherwise.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace igms::voice {

enum class Command {
  kFreeze,
  kRange,
  kUnfreeze,
  kBox,
  kCylinder,
  kMark,
  kUnmark,
  kRemovePoints,
  kWireframe,
  kSolid,
  kRemoveModel,
};

// The system's state, as the control client knows it.
enum class OperatorState {
  kVerification,
  kModelBuilding,
  kAwaitingType,  // four marks placed; "Is object a box or a cylinder?" was asked
};

struct CommandInfo {
  Command command;
  std::string_view code;    // two ASCII digits, as sent on the Dragon serial line
  std::string_view phrase;  // the words the operator says, lower case, single spaces
};

// Every command, in code order.
std::span<const CommandInfo> AllCommands();
const CommandInfo& Info(Command command);
std::string_view Code(Command command);
std::string_view Phrase(Command command);
// nullopt for anything that is not exactly one of the codes above ("01", not "1").
std::optional<Command> CommandFromCode(std::string_view code);
// nullopt unless the text is exactly one phrase (case and extra spaces are ignored).
std::optional<Command> CommandFromPhrase(std::string_view text);

std::span<const OperatorState> AllStates();
// "verification", "model_building", "awaiting_type".
std::string_view StateName(OperatorState state);
// Accepts the names above, plus "building" and "type" as short forms.
std::optional<OperatorState> StateFromName(std::string_view name);

// The commands the recogniser listens for in a state, in code order.
std::span<const Command> ValidCommands(OperatorState state);
bool IsValid(OperatorState state, Command command);

// The state the system will most likely be in after a command recognised in `state`:
// freeze -> model building, unfreeze -> verification, box or cylinder -> model building,
// unmark or remove points while awaiting the type -> model building; everything else keeps
// the state. Only a prediction: the control client's word always wins.
OperatorState PredictNextState(OperatorState state, Command command);

}  // namespace igms::voice
