#include "device_daemons/serial/recording.h"

#include <fcntl.h>
#include <google/protobuf/io/zero_copy_stream_impl.h>
#include <google/protobuf/util/delimited_message_util.h>
#include <unistd.h>

#include <chrono>

#include "common/base/clock.h"

namespace igms::devices {

namespace pbu = google::protobuf::util;

const Stamp& StampOf(const Reading& r) {
  switch (r.device_case()) {
    case Reading::kViewer:
      return r.viewer().stamp();
    case Reading::kJoystick:
      return r.joystick().stamp();
    case Reading::kRanger:
      return r.ranger().stamp();
    case Reading::kPlatform:
      return r.platform().stamp();
    case Reading::kVoice:
      return r.voice().stamp();
    case Reading::DEVICE_NOT_SET:
      break;
  }
  return Stamp::default_instance();
}

Stamp* MutableStampOf(Reading* r) {
  switch (r->device_case()) {
    case Reading::kViewer:
      return r->mutable_viewer()->mutable_stamp();
    case Reading::kJoystick:
      return r->mutable_joystick()->mutable_stamp();
    case Reading::kRanger:
      return r->mutable_ranger()->mutable_stamp();
    case Reading::kPlatform:
      return r->mutable_platform()->mutable_stamp();
    case Reading::kVoice:
      return r->mutable_voice()->mutable_stamp();
    case Reading::DEVICE_NOT_SET:
      break;
  }
  return nullptr;
}

bool RecordingWriter::Open(const std::string& path, const std::string& device, std::string* error) {
  out_.open(path, std::ios::binary | std::ios::trunc);
  if (!out_) {
    *error = "cannot create recording " + path;
    return false;
  }
  RecordingHeader header;
  header.set_device(device);
  header.set_start_unix_ns(UnixNs());
  header.set_program("igms-" + device + "d");
  if (!pbu::SerializeDelimitedToOstream(header, &out_) || !out_.flush()) {
    *error = "cannot write recording " + path;
    return false;
  }
  return true;
}

bool RecordingWriter::Append(const Reading& reading) {
  return pbu::SerializeDelimitedToOstream(reading, &out_) && out_.flush();
}

Result<Recording> LoadRecording(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return ErrorMessage{"cannot open recording " + path};
  Recording rec;
  {
    google::protobuf::io::FileInputStream in(fd);
    bool eof = false;
    if (!pbu::ParseDelimitedFromZeroCopyStream(&rec.header, &in, &eof) ||
        rec.header.device().empty()) {
      ::close(fd);
      return ErrorMessage{path + " is not a device recording (no header)"};
    }
    while (true) {
      Reading reading;
      if (!pbu::ParseDelimitedFromZeroCopyStream(&reading, &in, &eof)) break;  // end or torn tail
      if (reading.device_case() == Reading::DEVICE_NOT_SET) {
        ::close(fd);
        return ErrorMessage{path + ": reading " + std::to_string(rec.readings.size() + 1) +
                            " holds no device"};
      }
      rec.readings.push_back(std::move(reading));
    }
  }
  ::close(fd);
  return rec;
}

Replayer::Replayer(Recording recording, double speed, bool loop)
    : recording_(std::move(recording)), speed_(speed), loop_(loop) {}

Replayer::~Replayer() { Stop(); }

void Replayer::Start(std::function<void(const Reading&)> on_reading) {
  running_ = true;
  thread_ = std::thread([this, on_reading = std::move(on_reading)] {
    do {
      if (recording_.readings.empty()) break;
      const int64_t first = StampOf(recording_.readings.front()).receive_monotonic_ns();
      const auto start = std::chrono::steady_clock::now();
      for (const Reading& original : recording_.readings) {
        if (!running_) return;
        if (speed_ > 0) {
          const double offset_ns =
              static_cast<double>(StampOf(original).receive_monotonic_ns() - first) / speed_;
          const auto due = start + std::chrono::nanoseconds(static_cast<int64_t>(offset_ns));
          while (running_ && std::chrono::steady_clock::now() < due) {
            std::this_thread::sleep_until(
                std::min(due, std::chrono::steady_clock::now() + std::chrono::milliseconds(50)));
          }
        }
        Reading r = original;
        if (Stamp* s = MutableStampOf(&r)) {
          s->set_receive_monotonic_ns(MonotonicNs());
          s->set_receive_unix_ns(UnixNs());
        }
        on_reading(r);
      }
    } while (loop_ && running_);
    finished_ = true;
  });
}

void Replayer::Stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

}  // namespace igms::devices
