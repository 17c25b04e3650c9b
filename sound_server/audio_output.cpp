#include "sound_server/audio_output.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <fstream>

namespace igms::sound {
namespace {

std::atomic<bool> g_opened{false};

// OpenAL Soft reads ALSOFT_CONF once, at its first call; the file must exist by then.
std::string WriteAlsoftConfig(const std::string& driver, const OutputOptions& options) {
  char name[] = "/tmp/igms-sound-alsoft-XXXXXX";
  const int fd = mkstemp(name);
  if (fd < 0) return "";
  close(fd);
  std::ofstream out(name);
  out << "[general]\n"
      << "drivers=" << driver << "\n"
      << "channels=mono\n"
      << "sample-type=int16\n"
      << "frequency=" << options.wave_rate << "\n"
      << "period_size=" << options.period_frames << "\n";
  if (driver == "wave") out << "[wave]\nfile=" << options.wave_file << "\n";
  return out ? std::string(name) : "";
}

// Tries the default device in a child process, so a failure leaves this process's OpenAL
// unconfigured and free to choose a fallback backend.
bool DefaultDeviceOpens(const std::string& device) {
  const pid_t pid = fork();
  if (pid < 0) return true;  // cannot probe: let the real open report the failure
  if (pid == 0) {
    // The real open, later, reports the failure; the probe's backend chatter is noise.
    const int null_fd = open("/dev/null", O_WRONLY);
    if (null_fd >= 0) dup2(null_fd, STDERR_FILENO);
    ALCdevice* opened = alcOpenDevice(device.empty() ? nullptr : device.c_str());
    _exit(opened != nullptr ? 0 : 1);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
  }
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

std::string NoDeviceMessage(const OutputOptions& options) {
  return "no audio device: OpenAL could not open " +
         (options.device.empty() ? std::string("the default output device")
                                 : "the device '" + options.device + "'") +
         " (is there a sound card?). Use --output null to mix into nothing, --output wave "
         "--wave-file FILE to write what is played to a file, or --fallback null|wave to do "
         "so whenever no device is found";
}

}  // namespace

bool OutputOptions::Check(std::string* error) const {
  for (const std::string* mode : {&output, &fallback}) {
    if (*mode != "default" && *mode != "null" && *mode != "wave" &&
        !(mode == &fallback && *mode == "none")) {
      *error = "unknown output '" + *mode + "' (default, null or wave; fallback also none)";
      return false;
    }
  }
  if (fallback == "default") {
    *error = "the fallback cannot be 'default'";
    return false;
  }
  if ((output == "wave" || fallback == "wave") && wave_file.empty()) {
    *error = "the wave output needs a file (--wave-file)";
    return false;
  }
  if (wave_rate < 8000 || wave_rate > 192000) {
    *error = "the wave rate must be 8000-192000 Hz";
    return false;
  }
  if (period_frames < 64 || period_frames > 8192) {
    *error = "the period must be 64-8192 frames";
    return false;
  }
  return true;
}

AudioOutput::~AudioOutput() {
  alcMakeContextCurrent(nullptr);
  if (context_ != nullptr) alcDestroyContext(context_);
  if (device_ != nullptr) alcCloseDevice(device_);
  if (!config_file_.empty()) std::remove(config_file_.c_str());
}

bool AudioOutput::connected() const {
  if (!alcIsExtensionPresent(device_, "ALC_EXT_disconnect")) return true;
  ALCint connected = ALC_TRUE;
  alcGetIntegerv(device_, alcGetEnumValue(device_, "ALC_CONNECTED"), 1, &connected);
  return connected != ALC_FALSE;
}

OutputResult OpenOutput(const OutputOptions& options) {
  OutputResult result;
  if (std::string error; !options.Check(&error)) {
    result.error = "audio output: " + error;
    return result;
  }
  if (g_opened.exchange(true)) {
    result.error = "audio output: already opened once in this process";
    return result;
  }
  std::string mode = options.output;
  if (mode == "default" && options.fallback != "none" && !DefaultDeviceOpens(options.device)) {
    result.warning =
        NoDeviceMessage(options) + "; falling back to the " + options.fallback + " output";
    mode = options.fallback;
  }
  std::unique_ptr<AudioOutput> out(new AudioOutput());
  out->output_ = mode;
  if (mode != "default") {
    out->config_file_ = WriteAlsoftConfig(mode, options);
    if (out->config_file_.empty()) {
      result.error = "audio output: cannot write OpenAL's configuration to /tmp";
      return result;
    }
    // OpenAL Soft takes its configuration from the environment only. OpenOutput runs once, as
    // the program starts, before it starts a thread: setenv races with nothing.
    // NOLINTNEXTLINE(concurrency-mt-unsafe): no other thread yet (see above)
    setenv("ALSOFT_CONF", out->config_file_.c_str(), 1);
    // NOLINTNEXTLINE(concurrency-mt-unsafe): no other thread yet (see above)
    setenv("ALSOFT_DRIVERS", mode.c_str(), 1);
  }
  const char* name =
      (mode == "default" && !options.device.empty()) ? options.device.c_str() : nullptr;
  out->device_ = alcOpenDevice(name);
  if (out->device_ == nullptr) {
    result.error = mode == "default" ? NoDeviceMessage(options)
                   : mode == "wave"  ? "audio output: OpenAL cannot write the wave file '" +
                                          options.wave_file + "'"
                                    : "audio output: OpenAL's null output cannot be opened";
    return result;
  }
  out->context_ = alcCreateContext(out->device_, nullptr);
  if (out->context_ == nullptr || alcMakeContextCurrent(out->context_) != ALC_TRUE) {
    result.error = "audio output: OpenAL cannot create a context on '" +
                   std::string(alcGetString(out->device_, ALC_DEVICE_SPECIFIER)) + "'";
    return result;
  }
  const ALCchar* spec = alcIsExtensionPresent(nullptr, "ALC_ENUMERATE_ALL_EXT")
                            ? alcGetString(out->device_, ALC_ALL_DEVICES_SPECIFIER)
                            : alcGetString(out->device_, ALC_DEVICE_SPECIFIER);
  out->device_name_ = spec != nullptr ? spec : "";
  alcGetIntegerv(out->device_, ALC_FREQUENCY, 1, &out->sample_rate_);
  result.output = std::move(out);
  return result;
}

}  // namespace igms::sound
