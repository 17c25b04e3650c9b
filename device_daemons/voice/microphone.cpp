#include "device_daemons/voice/microphone.h"

#include <AL/al.h>
#include <AL/alc.h>
#include <AL/alext.h>

#include "device_daemons/voice/audio.h"

namespace igms::voice {

struct Microphone::Impl {
  ALCdevice* device = nullptr;
  ~Impl() {
    if (device) {
      alcCaptureStop(device);
      alcCaptureCloseDevice(device);
    }
  }
};

Microphone::Microphone(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Microphone::~Microphone() = default;

std::unique_ptr<Microphone> Microphone::Open(const std::string& device, std::string* error) {
  auto impl = std::make_unique<Impl>();
  // Half a second of buffer: the caller polls far more often than that.
  impl->device = alcCaptureOpenDevice(device.empty() ? nullptr : device.c_str(), kModelSampleRate,
                                      AL_FORMAT_MONO16, kModelSampleRate / 2);
  if (impl->device == nullptr) {
    if (error) {
      *error = "cannot open the capture device " +
               (device.empty() ? std::string("(default)") : "'" + device + "'") +
               " at 16 kHz mono; is there a microphone?";
    }
    return nullptr;
  }
  alcCaptureStart(impl->device);
  return std::unique_ptr<Microphone>(new Microphone(std::move(impl)));
}

bool Microphone::Read(std::vector<int16_t>& out) {
  ALCint available = 0;
  alcGetIntegerv(impl_->device, ALC_CAPTURE_SAMPLES, 1, &available);
  if (alcGetError(impl_->device) != ALC_NO_ERROR) return false;
  if (available > 0) {
    const size_t start = out.size();
    out.resize(start + available);
    alcCaptureSamples(impl_->device, out.data() + start, available);
  }
  ALCint connected = 1;
  alcGetIntegerv(impl_->device, ALC_CONNECTED, 1, &connected);
  return connected != 0;
}

std::vector<std::string> Microphone::DeviceNames() {
  std::vector<std::string> names;
  const ALCchar* list = alcGetString(nullptr, ALC_CAPTURE_DEVICE_SPECIFIER);
  while (list && *list) {
    names.emplace_back(list);
    list += names.back().size() + 1;
  }
  return names;
}

}  // namespace igms::voice
