// Opening the OpenAL output the sound server plays into.
//
// Three outputs:
//   default  the system's audio device through OpenAL Soft (its own configuration and
//            environment decide which; `device` names one of OpenAL's devices if not empty)
//   null     OpenAL Soft's null backend: everything is mixed in real time, nothing is heard
//   wave     OpenAL Soft's wave writer: what would be heard is written, in real time, to
//            `wave_file` (16-bit mono WAV at `wave_rate` Hz), for tests and benchmarks
// A machine without a sound card cannot open `default`; OpenOutput then says so and, when
// `fallback` is "null" or "wave", opens that instead. Because OpenAL Soft reads its backend
// choice once per process, the output is chosen before the first OpenAL call: a machine
// without a device is detected by a throw-away child process, and a process opens at most
// one AudioOutput in its life.
#pragma once

#include <AL/al.h>
#include <AL/alc.h>

#include <memory>
#include <optional>
#include <string>

namespace igms::sound {

struct OutputResult;

struct OutputOptions {
  std::string output = "default";  // "default", "null" or "wave"
  std::string device;              // default only: an OpenAL device name; "" = its default
  std::string wave_file;           // wave only: where the audio is written
  int wave_rate = 22050;           // wave only: Hz
  int period_frames = 256;         // null and wave: mixing period, frames (sets latency)
  std::string fallback = "none";   // "none", "null" or "wave": used when default fails

  // False, with what is wrong in *error, when invalid.
  bool Check(std::string* error) const;
};

// An open OpenAL device with a current context. Closing it finishes the wave file.
class AudioOutput {
 public:
  ~AudioOutput();
  AudioOutput(const AudioOutput&) = delete;
  AudioOutput& operator=(const AudioOutput&) = delete;

  ALCdevice* device() const { return device_; }
  // "default", "null" or "wave": what was actually opened (after any fallback).
  const std::string& output() const { return output_; }
  // OpenAL's name for the device ("No Output", "Wave File Writer", "ALSA Default", ...).
  const std::string& device_name() const { return device_name_; }
  int sample_rate() const { return sample_rate_; }
  // False once OpenAL reports the device gone (ALC_EXT_disconnect).
  bool connected() const;

 private:
  friend OutputResult OpenOutput(const OutputOptions& options);
  AudioOutput() = default;
  ALCdevice* device_ = nullptr;
  ALCcontext* context_ = nullptr;
  std::string output_;
  std::string device_name_;
  std::string config_file_;  // our temporary OpenAL Soft configuration, removed on close
  int sample_rate_ = 0;
};

struct OutputResult {
  std::unique_ptr<AudioOutput> output;
  std::string error;    // when output is empty: why, and what to do
  std::string warning;  // when a fallback was taken: why the default output failed
};

// Opens the output `options` ask for. Call once per process, before any other OpenAL call and
// before the program starts a thread (it sets OpenAL Soft's environment variables).
OutputResult OpenOutput(const OutputOptions& options);

}  // namespace igms::sound
