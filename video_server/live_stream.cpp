#include "video_server/live_stream.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <opencv2/imgproc.hpp>
#include <tuple>

#include "common/base/clock.h"
#include "video_server/proto_convert.h"

namespace igms::video {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kDefaultFps = 30.0;
constexpr double kMaxFps = 120.0;

Clock::duration Period(double fps) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / fps));
}

}  // namespace

struct LiveStreamer::Subscriber {
  LiveRequest request;
  LiveSink sink;
  Clock::duration period;
  Clock::time_point next_due;
};

LiveStreamer::LiveStreamer(LiveCapture capture) : capture_(std::move(capture)) {
  thread_ = std::thread([this] { Run(); });
}

LiveStreamer::~LiveStreamer() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

std::string LiveStreamer::Add(const LiveRequest& request, LiveSink sink) {
  if (!std::isfinite(request.fps()) || request.fps() < 0 || request.fps() > kMaxFps) {
    return "live fps must be in 0..120 (0: 30)";
  }
  if ((request.width() == 0) != (request.height() == 0)) {
    return "give both live width and height, or neither";
  }
  if (request.width() != 0 && (request.width() < 16 || request.width() > 8192 ||
                               request.height() < 16 || request.height() > 8192)) {
    return "live width and height must be in 16..8192";
  }
  auto subscriber = std::make_shared<Subscriber>();
  subscriber->request = request;
  subscriber->sink = std::move(sink);
  subscriber->period = Period(request.fps() > 0 ? request.fps() : kDefaultFps);
  subscriber->next_due = Clock::now();
  {
    std::lock_guard lock(mutex_);
    subscribers_.push_back(std::move(subscriber));
    ++added_;
  }
  changed_.notify_all();
  return "";
}

size_t LiveStreamer::subscribers() const {
  std::lock_guard lock(mutex_);
  return subscribers_.size();
}

uint64_t LiveStreamer::captures() const {
  std::lock_guard lock(mutex_);
  return captures_;
}

std::string LiveStreamer::last_error() const {
  std::lock_guard lock(mutex_);
  return last_error_;
}

void LiveStreamer::Run() {
  // Key of one way of sending a capture: size, encoding, side.
  using Variant = std::tuple<int, int, int, int>;
  uint64_t sequence = 0;
  for (;;) {
    std::vector<std::shared_ptr<Subscriber>> due;
    {
      std::unique_lock lock(mutex_);
      changed_.wait(lock, [&] { return stop_ || !subscribers_.empty(); });
      if (stop_) return;
      Clock::time_point earliest = Clock::time_point::max();
      for (const auto& s : subscribers_) earliest = std::min(earliest, s->next_due);
      const uint64_t added = added_;
      changed_.wait_until(lock, earliest, [&] { return stop_ || added_ != added; });
      if (stop_) return;
      const auto now = Clock::now();
      for (const auto& s : subscribers_) {
        if (s->next_due <= now) due.push_back(s);
      }
    }
    if (due.empty()) continue;  // a subscriber was added meanwhile; recompute

    CaptureResult captured = capture_();
    const auto after = Clock::now();
    {
      std::lock_guard lock(mutex_);
      ++captures_;
      last_error_ = captured.ok() ? "" : captured.error;
    }
    for (const auto& s : due) {
      // The next due time keeps the subscriber's rate; a late capture does not bunch frames.
      s->next_due = std::max(s->next_due + s->period, after);
    }
    if (!captured.ok()) {
      spdlog::warn("live capture failed: {}", captured.error);
      continue;
    }
    ++sequence;
    const StereoImages& images = *captured.images;
    std::map<Variant, std::shared_ptr<LiveFrame>> made;
    std::vector<std::shared_ptr<Subscriber>> gone;
    for (const auto& s : due) {
      const LiveRequest& r = s->request;
      const wire::ImageEncoding encoding =
          wire::EncodingFromProto(r.encoding(), wire::ImageEncoding::kRaw);
      const Variant key{r.width(), r.height(), static_cast<int>(encoding), r.side()};
      std::shared_ptr<LiveFrame>& frame = made[key];
      if (!frame) {
        frame = std::make_shared<LiveFrame>();
        frame->set_sequence(sequence);
        frame->set_capture_unix_ns(images.left_capture_unix_ns);
        ToProto(images.pose, frame->mutable_pose());
        for (bool left : {true, false}) {
          if (r.side() == (left ? RIGHT : LEFT)) continue;
          cv::Mat image = left ? images.left : images.right;
          if (r.width() != 0 && (r.width() != image.cols || r.height() != image.rows)) {
            cv::Mat resized;
            cv::resize(image, resized, cv::Size(r.width(), r.height()), 0, 0, cv::INTER_AREA);
            image = resized;
          }
          wire::EncodeRegion(image, cv::Rect(0, 0, image.cols, image.rows), encoding,
                             left ? frame->mutable_left() : frame->mutable_right());
        }
      }
      frame->set_send_unix_ns(UnixNs());
      if (!s->sink(*frame)) gone.push_back(s);
    }
    if (!gone.empty()) {
      std::lock_guard lock(mutex_);
      std::erase_if(subscribers_, [&](const auto& s) {
        return std::find(gone.begin(), gone.end(), s) != gone.end();
      });
      spdlog::info("live: {} subscriber(s) left, {} remain", gone.size(), subscribers_.size());
    }
  }
}

}  // namespace igms::video
