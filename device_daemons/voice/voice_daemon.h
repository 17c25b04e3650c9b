// igms-voiced's body: the voice device behind igms.devices.VoiceService
//   Live(SubscribeRequest) -> stream of VoiceState, one per accepted command
//   Status(GetStatusRequest) -> LinkStatus (rejections are in its message)
//   SetOperatorState(SetOperatorStateRequest): the control client's word on the system's
//     state; the grammar follows it from the next utterance (the thesis's flaw fixed)
// and igms.devices.SimService.Inject, which takes a VoiceCommand or a spoken phrase and
// answers what was heard (SimInjectResponse.heard).
//
// The device is one of
//   - a Dragon speech PC on a serial port (--serial), or its simulator on a
//     pseudo-terminal (--simulate): dragon_driver.h, dragon_sim.h;
//   - the recogniser listening to a microphone or sound files (SpeechListener), when
//     VoiceDaemonOptions::listen is set; then Inject takes a spoken phrase, which
//     espeak-ng says and the real recogniser decodes;
//   - a recording (--replay).
// All publish the same VoiceState. See daemon_base.h.
#pragma once

#include <optional>

#include "device_daemons/serial/daemon_base.h"
#include "device_daemons/voice/dragon_driver.h"
#include "device_daemons/voice/speech_listener.h"

namespace igms::voice {

struct VoiceDaemonOptions {
  OperatorState initial_state = OperatorState::kVerification;
  // Set: the recogniser is the device (DaemonOptions' serial link is then unused).
  std::optional<SpeechListenerOptions> listen;
};

// What the voice daemon's own keys and flags say, from which its main builds
// VoiceDaemonOptions.
struct VoiceConfig {
  std::string state = "verification";  // the operator's state at start
  bool microphone = false;             // the recogniser on a microphone
  std::string device;                  // the microphone's capture device; empty: the system's
  std::string model_dir = RecognizerOptions().model_dir;  // the key's made absolute
};

// The voice daemon's keys (processes.NAME): the daemon's shared ones (DaemonKeys, bound to
// `daemon`), and state, microphone, device and model_dir bound to `config` with their flags.
config::Keys VoiceKeys(VoiceConfig* config, devices::DaemonConfig* daemon);

class VoiceDaemon : public devices::DaemonBase<devices::VoiceState> {
 public:
  VoiceDaemon(boost::asio::io_context& io, devices::DaemonOptions options,
              net::ServerOptions server, VoiceDaemonOptions voice = {});
  ~VoiceDaemon() override;

 private:
  std::unique_ptr<devices::SimulatedDevice> MakeSimulator(std::string* error) override;
  bool StartDevice(const devices::SerialLinkOptions& link, std::string* error) override;
  void StopDevice() override;
  devices::LinkStatus DeviceStatus() const override;
  bool InjectInput(const devices::SimInjectRequest& request, devices::SimulatedDevice& sim,
                   devices::SimInjectResponse* response, std::string* error) override;
  void RegisterMethods(net::Server& server) override;

  VoiceDaemonOptions voice_;
  std::unique_ptr<DragonDriver> driver_;
  std::unique_ptr<SpeechListener> listener_;
};

}  // namespace igms::voice
