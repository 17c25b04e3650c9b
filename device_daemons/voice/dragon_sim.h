// A simulated Dragon Writer speech PC (dragon_protocol.h) for a pseudo-terminal
// (device_daemons/serial/pty_host.h). The operator's speech is injected as a command or a
// phrase (Say); the simulated recogniser keeps the command language's state machine, as
// the Dragon did (Cooke, section 2.1.6, figure 2-3): a word valid in its state is sent as
// its code after recognition_ns and moves the state on (PredictNextState), any other word
// is not heard. Unlike the thesis's Dragon it also takes the host's "S d" and follows the
// system's state. It answers every probe and state change with "00".
//
// Threading: the PtyHost calls it on its thread; Say and the accessors are called through
// PtyHost::WithDevice.
#pragma once

#include <deque>
#include <string>

#include "device_daemons/serial/pty_host.h"
#include "device_daemons/voice/dragon_protocol.h"

namespace igms::voice {

struct DragonSimOptions {
  OperatorState initial_state = OperatorState::kVerification;
  int64_t recognition_ns = 20'000'000;  // from the end of the word to the code going out
};

// Why a phrase was not sent.
enum class Heard { kSent, kNotACommand, kNotValidInState };

class DragonSim : public devices::SimulatedDevice {
 public:
  explicit DragonSim(DragonSimOptions options = {});
  std::vector<std::string> OnInput(std::string_view bytes, int64_t now_ns) override;
  std::vector<std::string> Poll(int64_t now_ns, int64_t* next_wake_ns) override;

  // The operator says a command, or any phrase (matched as CommandFromPhrase does).
  Heard Say(Command command, int64_t now_ns);
  Heard Say(std::string_view phrase, int64_t now_ns);

  OperatorState state() const { return state_; }
  uint64_t sent() const { return sent_; }
  uint64_t not_heard() const { return not_heard_; }
  uint64_t bad_requests() const { return parser_.bad_frames(); }

 private:
  DragonSimOptions options_;
  OperatorState state_;
  dragon::HostParser parser_;
  struct Due {
    int64_t at_ns;
    std::string bytes;
  };
  std::deque<Due> due_;
  uint64_t sent_ = 0, not_heard_ = 0;
};

}  // namespace igms::voice
