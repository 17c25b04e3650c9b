// A microphone through OpenAL capture: 16 kHz mono 16-bit samples, pulled by the caller.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace igms::voice {

class Microphone {
 public:
  // Opens and starts a capture device ("" is the system's default). nullptr, with *error
  // set naming the device, when there is none or it cannot capture at 16 kHz mono.
  static std::unique_ptr<Microphone> Open(const std::string& device, std::string* error);
  ~Microphone();
  Microphone(const Microphone&) = delete;
  Microphone& operator=(const Microphone&) = delete;

  // Appends whatever has been captured since the last call (possibly nothing); never blocks.
  // False when the device has failed (unplugged).
  bool Read(std::vector<int16_t>& out);
  // The capture devices OpenAL knows of.
  static std::vector<std::string> DeviceNames();

 private:
  struct Impl;
  explicit Microphone(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace igms::voice
