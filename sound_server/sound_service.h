// The sound server's methods on the network (proto/igms/sound.proto, docs/protocol-sound.md):
// each request is checked, handed to the Engine and its outcome turned into a response or
// an error (BAD_REQUEST, NOT_FOUND, UNAVAILABLE with the engine's message).
//
// Every handler is quick (OpenAL calls and a lock), so all run on the network thread.
#pragma once

#include <string>

#include "common/net/server.h"
#include "sound_server/engine.h"

namespace igms::sound {

inline const std::string kPlayMethod = "igms.sound.SoundService.Play";
inline const std::string kStopMethod = "igms.sound.SoundService.Stop";
inline const std::string kListBankMethod = "igms.sound.SoundService.ListBank";
inline const std::string kStatusMethod = "igms.sound.SoundService.Status";
inline const std::string kSetVolumeMethod = "igms.sound.SoundService.SetVolume";

// Registers every SoundService method on `server`; `engine` must outlive it.
void RegisterSoundService(net::Server& server, Engine& engine);

}  // namespace igms::sound
