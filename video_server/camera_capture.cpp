#include "video_server/camera_capture.h"

#include <spdlog/spdlog.h>

#include <cctype>
#include <condition_variable>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <thread>

#include "common/base/clock.h"

namespace igms::video {
namespace {

using Clock = std::chrono::steady_clock;

bool IsIndex(const std::string& device) {
  if (device.empty() || device.size() > 4) return false;
  for (char c : device) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  }
  return true;
}

// OpenCV's capture backends (GStreamer above all) set themselves up on the first open and
// are not safe to open from two threads at once: the two cameras' readers crashed the
// process doing so. Opening is rare (start-up, retries), so all opens take turns.
std::mutex& OpenMutex() {
  static std::mutex mutex;
  return mutex;
}

// One device, read continuously on its own thread; the newest frame wins.
class DeviceReader {
 public:
  DeviceReader(std::string role, const CameraCaptureOptions& options)
      : role_(std::move(role)),
        device_(role_ == "right" ? options.right : options.left),
        options_(options) {
    thread_ = std::thread([this] { Run(); });
  }

  ~DeviceReader() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    changed_.notify_all();
    thread_.join();
  }

  // Waits until a frame read at or after `since_ns` (wall clock) arrives or `deadline`
  // passes.
  bool WaitNewer(int64_t since_ns, Clock::time_point deadline, cv::Mat& frame, int64_t& time_ns,
                 std::string& error) {
    std::unique_lock lock(mutex_);
    changed_.wait_until(lock, deadline, [&] { return latest_time_ns_ >= since_ns || stop_; });
    if (latest_time_ns_ < since_ns) {
      error = role_ + " camera " + device_ + ": " +
              (status_.empty()
                   ? "no frame within " + std::to_string(options_.frame_timeout.count()) + " ms"
                   : status_);
      return false;
    }
    frame = latest_.clone();
    time_ns = latest_time_ns_;
    return true;
  }

 private:
  void Run() {
    cv::VideoCapture capture;
    const auto pace = options_.pace_fps > 0
                          ? std::chrono::duration_cast<Clock::duration>(
                                std::chrono::duration<double>(1.0 / options_.pace_fps))
                          : Clock::duration::zero();
    auto next_read = Clock::now();
    while (!Stopping()) {
      if (!capture.isOpened() && !Open(capture)) {
        SetStatus("cannot open the device (retrying every " +
                  std::to_string(options_.retry_interval.count()) + " ms)");
        SleepFor(options_.retry_interval);
        continue;
      }
      if (pace > Clock::duration::zero()) {
        SleepFor(std::chrono::duration_cast<std::chrono::milliseconds>(next_read - Clock::now()));
        next_read = std::max(next_read + pace, Clock::now());
      }
      cv::Mat frame;
      if (!capture.read(frame) || frame.empty()) {
        capture.release();
        SetStatus("stopped delivering frames (reopening every " +
                  std::to_string(options_.retry_interval.count()) + " ms)");
        SleepFor(options_.retry_interval);
        continue;
      }
      const int64_t now = UnixNs();
      if (!options_.colour && frame.channels() != 1) {
        cv::Mat grey;
        cv::cvtColor(frame, grey, frame.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
        frame = grey;
      }
      {
        std::lock_guard lock(mutex_);
        latest_ = frame;
        latest_time_ns_ = now;
        status_.clear();
      }
      changed_.notify_all();
    }
  }

  bool Open(cv::VideoCapture& capture) {
    std::lock_guard open_lock(OpenMutex());
    const bool ok = IsIndex(device_) ? capture.open(std::stoi(device_)) : capture.open(device_);
    if (!ok || !capture.isOpened()) {
      capture.release();
      spdlog::warn("{} camera {}: cannot open; retrying in {} ms", role_, device_,
                   options_.retry_interval.count());
      return false;
    }
    if (options_.width > 0) capture.set(cv::CAP_PROP_FRAME_WIDTH, options_.width);
    if (options_.height > 0) capture.set(cv::CAP_PROP_FRAME_HEIGHT, options_.height);
    spdlog::info("{} camera {}: open ({})", role_, device_, capture.getBackendName());
    return true;
  }

  bool Stopping() {
    std::lock_guard lock(mutex_);
    return stop_;
  }

  void SetStatus(std::string status) {
    std::lock_guard lock(mutex_);
    status_ = std::move(status);
  }

  // Sleeps, waking early when the reader is being stopped.
  void SleepFor(std::chrono::milliseconds duration) {
    if (duration <= std::chrono::milliseconds::zero()) return;
    std::unique_lock lock(mutex_);
    changed_.wait_for(lock, duration, [&] { return stop_; });
  }

  const std::string role_;
  const std::string device_;
  const CameraCaptureOptions options_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  bool stop_ = false;
  cv::Mat latest_;
  int64_t latest_time_ns_ = 0;
  std::string status_ = "opening the device (first attempt still running)";
  std::thread thread_;
};

class CameraCapture : public CaptureBackend {
 public:
  explicit CameraCapture(const CameraCaptureOptions& options) : options_(options) {
    left_ = std::make_unique<DeviceReader>(options.side_by_side ? "side-by-side" : "left", options);
    if (!options.side_by_side) right_ = std::make_unique<DeviceReader>("right", options);
  }

  CaptureResult Capture(const PoseStamp& pose) override {
    const auto deadline = Clock::now() + options_.frame_timeout;
    const int64_t since = UnixNs();
    StereoImages images;
    images.pose = pose;
    std::string error;
    cv::Mat left;
    if (!left_->WaitNewer(since, deadline, left, images.left_capture_unix_ns, error)) {
      return CaptureResult::Error(error);
    }
    if (right_) {
      images.left = left;
      if (!right_->WaitNewer(since, deadline, images.right, images.right_capture_unix_ns, error)) {
        return CaptureResult::Error(error);
      }
    } else {
      if (left.cols % 2 != 0) {
        return CaptureResult::Error("side-by-side camera " + options_.left + ": frame width " +
                                    std::to_string(left.cols) + " is odd, cannot split it");
      }
      const int half = left.cols / 2;
      images.left = left.colRange(0, half).clone();
      images.right = left.colRange(half, left.cols).clone();
      images.right_capture_unix_ns = images.left_capture_unix_ns;
    }
    if (std::string problem = CheckStereoImages(images); !problem.empty()) {
      return CaptureResult::Error("cameras " + options_.left + " and " + options_.right + ": " +
                                  problem);
    }
    return CaptureResult::Ok(std::move(images));
  }

  std::string Describe() const override {
    if (options_.side_by_side) return "camera: side-by-side " + options_.left;
    return "camera: left " + options_.left + ", right " + options_.right;
  }

 private:
  CameraCaptureOptions options_;
  std::unique_ptr<DeviceReader> left_;
  std::unique_ptr<DeviceReader> right_;
};

}  // namespace

bool CameraCaptureOptions::Check(std::string* error) const {
  if (left.empty()) {
    *error = "the camera backend needs a left device (or a side-by-side one)";
    return false;
  }
  if (!side_by_side && right.empty()) {
    *error = "the camera backend needs a right device unless side_by_side is set";
    return false;
  }
  if (side_by_side && !right.empty()) {
    *error = "a side-by-side camera takes no right device";
    return false;
  }
  if (width < 0 || height < 0 || width > 16384 || height > 16384) {
    *error = "absurd frame size";
    return false;
  }
  if (pace_fps < 0 || pace_fps > 1000) {
    *error = "pace_fps must be in [0, 1000]";
    return false;
  }
  if (frame_timeout.count() <= 0 || retry_interval.count() <= 0) {
    *error = "frame_timeout and retry_interval must be positive";
    return false;
  }
  return true;
}

std::unique_ptr<CaptureBackend> MakeCameraCapture(const CameraCaptureOptions& options,
                                                  std::string* error) {
  if (std::string problem; !options.Check(&problem)) {
    if (error) *error = problem;
    return nullptr;
  }
  return std::make_unique<CameraCapture>(options);
}

}  // namespace igms::video
