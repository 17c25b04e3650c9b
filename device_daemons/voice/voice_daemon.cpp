#include "device_daemons/voice/voice_daemon.h"

#include <optional>

#include "common/base/clock.h"
#include "device_daemons/voice/dragon_sim.h"
#include "device_daemons/voice/voice_proto.h"

namespace igms::voice {

config::Keys VoiceKeys(VoiceConfig* c, devices::DaemonConfig* daemon) {
  config::Keys keys = devices::DaemonKeys(daemon);
  keys.BindChoice("state", &c->state, {"verification", "model_building", "awaiting_type"},
                  "the operator's state at start", "state");
  keys.Bind("microphone", &c->microphone,
            "recognise speech from a microphone instead of a Dragon on a serial line",
            "microphone");
  keys.Bind("device", &c->device, "capture device for the microphone (default: the system's)",
            "device");
  keys.BindPath("model_dir", &c->model_dir,
                "recogniser: the pocketsphinx en-us model folder, or an operator's "
                "adapted model (igms-voice-adapt)",
                "model-dir");
  return keys;
}

namespace {

// The Dragon gives a command at most every few tenths of a second; subscribers asking
// for less get the newest.
constexpr double kMaxRateHz = 10.0;

}  // namespace

VoiceDaemon::VoiceDaemon(boost::asio::io_context& io, devices::DaemonOptions options,
                         net::ServerOptions server, VoiceDaemonOptions voice)
    : DaemonBase(io, "voice", "igms.devices.VoiceService", std::move(options), std::move(server),
                 kMaxRateHz),
      voice_(std::move(voice)) {}

VoiceDaemon::~VoiceDaemon() {
  if (listener_) listener_->Stop();
}

std::unique_ptr<devices::SimulatedDevice> VoiceDaemon::MakeSimulator(std::string*) {
  DragonSimOptions o;
  o.initial_state = voice_.initial_state;
  return std::make_unique<DragonSim>(o);
}

bool VoiceDaemon::StartDevice(const devices::SerialLinkOptions& link, std::string* error) {
  auto publish = [this](const devices::VoiceState& s) { hub().Publish(s); };
  if (voice_.listen) {
    SpeechListenerOptions o = *voice_.listen;
    o.recognizer.initial_state = voice_.initial_state;
    listener_ = SpeechListener::Start(o, publish, error);
    return listener_ != nullptr;
  }
  if (!link.Check(error)) return false;
  devices::SerialLinkOptions l = link;
  // The probes keep the line alive: silent for three probe periods is stale.
  l.silence_timeout = std::max(
      l.silence_timeout, std::chrono::milliseconds(static_cast<int>(3000 / dragon::kProbeHz)));
  driver_ = std::make_unique<DragonDriver>(io_, l, voice_.initial_state, publish);
  driver_->Start();
  return true;
}

void VoiceDaemon::StopDevice() {
  if (listener_) listener_->Stop();
  if (driver_) driver_->Stop();
}

devices::LinkStatus VoiceDaemon::DeviceStatus() const {
  if (listener_) return listener_->status();
  if (!driver_) return devices::LinkStatus();
  devices::LinkStatus s = driver_->status();
  s.set_message(s.message() + "; state " + std::string(StateName(driver_->state())) + ", " +
                std::to_string(driver_->rejected()) + " rejected (not valid in the state)");
  return s;
}

bool VoiceDaemon::InjectInput(const devices::SimInjectRequest& request,
                              devices::SimulatedDevice& sim, devices::SimInjectResponse* response,
                              std::string* error) {
  auto& dragon = static_cast<DragonSim&>(sim);
  const int64_t now = igms::MonotonicNs();
  std::optional<Command> command;
  std::string text;
  if (request.input_case() == devices::SimInjectRequest::kVoice) {
    command = FromProto(request.voice());
    if (!command) {
      *error = "not a voice command: " + std::to_string(request.voice());
      return false;
    }
    text = std::string(Phrase(*command));
  } else if (request.has_spoken()) {
    if (request.spoken().empty() || request.spoken().size() > 200) {
      *error = "a spoken phrase must have 1 to 200 characters";
      return false;
    }
    text = request.spoken();
    command = CommandFromPhrase(text);
  } else {
    *error = "the voice simulator takes a VoiceCommand or a spoken phrase (or a fault)";
    return false;
  }
  // The Dragon hears the words as they are; what it makes of them depends on the state.
  const OperatorState state = dragon.state();
  const Heard heard = command ? dragon.Say(*command, now) : dragon.Say(text, now);
  devices::SimHeard* out = response->mutable_heard();
  out->set_accepted(heard == Heard::kSent);
  if (command) out->set_command(ToProto(*command));
  out->set_text(text);
  out->set_state(ToProto(state));
  if (heard == Heard::kNotACommand) {
    out->set_detail("\"" + text + "\" is no command");
  } else if (heard == Heard::kNotValidInState) {
    out->set_detail("\"" + std::string(Phrase(*command)) + "\" is not valid in state " +
                    std::string(StateName(state)));
  }
  return true;
}

void VoiceDaemon::RegisterMethods(net::Server& server) {
  // Answered once the device has taken the state (the Dragon's acknowledgement, or its
  // timeout), so an utterance after the answer is decoded with the new grammar.
  server.HandleAsync<devices::SetOperatorStateRequest, devices::SetOperatorStateResponse>(
      "igms.devices.VoiceService.SetOperatorState",
      [this](const devices::SetOperatorStateRequest& req,
             net::Reply<devices::SetOperatorStateResponse> reply) {
        const auto state = FromProto(req.state());
        if (!state) {
          return reply(net::Status::Error(
              igms::BAD_REQUEST,
              "state must be VERIFICATION, MODEL_BUILDING or AWAITING_OBJECT_TYPE"));
        }
        if (listener_) listener_->SetState(*state);
        if (driver_) {
          driver_->SetState(*state, [reply] { reply(net::Status::Ok()); });
          return;
        }
        reply(net::Status::Ok());  // a replay has no grammar to change
      });
  if (!listener_) return;
  // The recogniser is no simulator, but it can hear a phrase spoken by espeak-ng: this
  // replaces the base's Inject, which would answer UNAVAILABLE. It answers once the phrase
  // is decoded, with what was heard.
  server.HandleAsync<devices::SimInjectRequest, devices::SimInjectResponse>(
      "igms.devices.SimService.Inject",
      [this](const devices::SimInjectRequest& req, net::Reply<devices::SimInjectResponse> reply) {
        std::string phrase;
        if (req.has_spoken()) {
          phrase = req.spoken();
        } else if (req.input_case() == devices::SimInjectRequest::kVoice) {
          const auto command = FromProto(req.voice());
          if (!command) return reply(net::Status::Error(igms::BAD_REQUEST, "not a voice command"));
          phrase = std::string(Phrase(*command));
        } else {
          return reply(net::Status::Error(
              igms::BAD_REQUEST,
              "the recogniser takes a spoken phrase or a VoiceCommand (no faults: it has no "
              "serial line)"));
        }
        std::string error;
        const bool queued = listener_->Say(phrase, &error, [reply](const devices::SimHeard& h) {
          devices::SimInjectResponse response;
          *response.mutable_heard() = h;
          reply(net::Status::Ok(), response);
        });
        if (!queued) reply(net::Status::Error(igms::BAD_REQUEST, error));
      });
}

}  // namespace igms::voice
