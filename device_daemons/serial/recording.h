// Record and replay of a daemon's reading stream (think VRPN's logging).
//
// File format: a varint-delimited igms.devices.RecordingHeader, then one varint-delimited
// igms.devices.Reading per reading, each carrying its original Stamp. Replay keeps the
// original spacing of receive_monotonic_ns, divided by `speed` (1 = the original rate,
// 10 = ten times faster, 0 = as fast as possible); replayed readings are stamped with the
// replay's receive times and keep their original sequence and device times.
#pragma once

#include <atomic>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "common/base/result.h"
#include "igms/devices.pb.h"

namespace igms::devices {

// The Stamp inside whichever device message the reading holds (a default one if empty).
const Stamp& StampOf(const Reading& reading);
Stamp* MutableStampOf(Reading* reading);

class RecordingWriter {
 public:
  // Creates (truncates) the file and writes the header. False with a message on failure.
  bool Open(const std::string& path, const std::string& device, std::string* error);
  bool Append(const Reading& reading);  // flushed, so a killed daemon loses at most one
  bool is_open() const { return out_.is_open(); }

 private:
  std::ofstream out_;
};

struct Recording {
  RecordingHeader header;
  std::vector<Reading> readings;
};

// Reads a whole recording. A truncated last record is dropped with no error (a recorder
// killed mid-write); anything else malformed is an error with a message.
Result<Recording> LoadRecording(const std::string& path);

// Plays a recording on its own thread, calling on_reading for each one.
class Replayer {
 public:
  Replayer(Recording recording, double speed, bool loop);
  ~Replayer();
  void Start(std::function<void(const Reading&)> on_reading);
  void Stop();
  bool finished() const { return finished_; }

 private:
  Recording recording_;
  double speed_;
  bool loop_;
  std::atomic<bool> running_{false};
  std::atomic<bool> finished_{false};
  std::thread thread_;
};

}  // namespace igms::devices
