#include "device_daemons/voice/dragon_sim.h"

#include <algorithm>

namespace igms::voice {

DragonSim::DragonSim(DragonSimOptions options) : options_(options), state_(options.initial_state) {}

std::vector<std::string> DragonSim::OnInput(std::string_view bytes, int64_t) {
  std::vector<std::string> out;
  for (char c : bytes) {
    if (parser_.Feed(static_cast<uint8_t>(c)) != devices::ParseResult::kGood) continue;
    if (parser_.request().state) state_ = *parser_.request().state;
    out.push_back(dragon::EncodeAlive());
  }
  return out;
}

std::vector<std::string> DragonSim::Poll(int64_t now_ns, int64_t* next_wake_ns) {
  std::vector<std::string> out;
  while (!due_.empty() && due_.front().at_ns <= now_ns) {
    out.push_back(std::move(due_.front().bytes));
    due_.pop_front();
  }
  if (!due_.empty()) *next_wake_ns = std::min(*next_wake_ns, due_.front().at_ns);
  return out;
}

Heard DragonSim::Say(Command command, int64_t now_ns) {
  if (!IsValid(state_, command)) {
    ++not_heard_;
    return Heard::kNotValidInState;
  }
  due_.push_back({now_ns + options_.recognition_ns, dragon::EncodeCommand(command)});
  state_ = PredictNextState(state_, command);
  ++sent_;
  return Heard::kSent;
}

Heard DragonSim::Say(std::string_view phrase, int64_t now_ns) {
  const auto command = CommandFromPhrase(phrase);
  if (!command) {
    ++not_heard_;
    return Heard::kNotACommand;
  }
  return Say(*command, now_ns);
}

}  // namespace igms::voice
