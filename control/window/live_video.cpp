#include "control/window/live_video.h"

#include <spdlog/spdlog.h>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <deque>
#include <mutex>
#include <thread>
#include <utility>  // before asio (Boost 1.74)

#include "common/base/clock.h"
#include "common/net/client.h"
#include "common/net/clock_offset.h"
#include "common/wire/image_message.h"
#include "igms/video.pb.h"

namespace igms::control {

struct LiveVideo::Impl : std::enable_shared_from_this<Impl> {
  LiveVideoOptions options;
  boost::asio::io_context io;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work{io.get_executor()};
  std::unique_ptr<net::Client> client;
  std::thread thread;

  mutable std::mutex mutex;
  StereoFrame newest;
  bool connected = false;
  int64_t last_frame_ns = 0;  // monotonic
  LiveStats stats;
  std::deque<int64_t> arrivals;  // monotonic, the last second
  video::OverlaySettings overlay;
  uint64_t grab_id = 0;  // the grab asked for, and when it has come, its pair
  std::optional<StereoFrame> grab;
  // The video server's clock minus this host's, from pings at each connection: a frame's
  // capture stamp is the video host's clock (common/net/clock_offset.h).
  std::optional<net::ClockOffset> clock;

  void OnFrame(const video::LiveFrame& f) {
    StereoFrame frame;
    frame.left = wire::DecodeProtoImage(f.left());
    frame.right = wire::DecodeProtoImage(f.right());
    if (frame.left.empty() || frame.right.empty()) return;
    frame.sequence = f.sequence();
    frame.capture_unix_ns = f.capture_unix_ns();
    frame.joints.assign(f.pose().joints_rad().begin(), f.pose().joints_rad().end());
    const int64_t now = MonotonicNs();
    std::lock_guard lock(mutex);
    if (newest.sequence && frame.sequence > newest.sequence + 1) {
      stats.skipped += frame.sequence - newest.sequence - 1;
    }
    stats.frames++;
    // Unknown until the pings have come back: the stamps as they are meanwhile.
    const int64_t captured =
        clock ? clock->ToLocalNs(frame.capture_unix_ns) : frame.capture_unix_ns;
    stats.latency_ms = static_cast<double>(UnixNs() - captured) / 1e6;
    arrivals.push_back(now);
    while (!arrivals.empty() && arrivals.front() < now - 1'000'000'000) arrivals.pop_front();
    stats.rate_fps = static_cast<double>(arrivals.size());
    last_frame_ns = now;
    newest = std::move(frame);
  }

  // Pings the video server for its clock's offset; on the network thread.
  void MeasureClock() {
    net::MeasureClockOffsetAsync(
        *client, 5, std::chrono::milliseconds(2000),
        [weak = weak_from_this()](std::optional<net::ClockOffset> offset, const std::string& why) {
          auto self = weak.lock();
          if (!self) return;
          if (!offset) {
            spdlog::warn("the window's live video: no clock offset of the video server: {}", why);
            return;
          }
          spdlog::info("the window's live video: the video server's clock offset {}",
                       offset->Describe());
          std::lock_guard lock(self->mutex);
          self->clock = offset;
          self->stats.clock_offset_ms = static_cast<double>(offset->offset_ns) / 1e6;
          self->stats.clock_bound_ms = static_cast<double>(offset->bound_ns()) / 1e6;
          self->stats.clock_pings = offset->samples;
        });
  }

  void GetOverlay() {
    client->Call<video::GetOverlayResponse>(
        "igms.video.VideoService.GetOverlay", video::GetOverlayRequest(),
        std::chrono::milliseconds(2000),
        [self = shared_from_this()](const net::Result<video::GetOverlayResponse>& r) {
          if (!r.ok()) return;
          std::lock_guard lock(self->mutex);
          self->overlay = r.value.settings();
        });
  }
};

std::unique_ptr<LiveVideo> LiveVideo::Start(LiveVideoOptions options) {
  auto impl = std::make_shared<Impl>();
  impl->options = std::move(options);
  net::ClientOptions client;
  client.host = impl->options.address.host;
  client.port = impl->options.address.port;
  client.name = impl->options.client_name;
  client.token = impl->options.token;
  client.connect_timeout = std::chrono::milliseconds(1000);
  client.max_backoff = std::chrono::milliseconds(1000);
  client.max_frame_bytes = kLiveMaxFrameBytes;
  impl->client = std::make_unique<net::Client>(impl->io, client);
  std::weak_ptr<Impl> weak = impl;
  impl->client->OnStateChange([weak](net::ConnectionState state, const std::string& why) {
    auto self = weak.lock();
    if (!self) return;
    {
      std::lock_guard lock(self->mutex);
      self->connected = state == net::ConnectionState::kConnected;
      if (self->connected) self->last_frame_ns = MonotonicNs();
    }
    if (state == net::ConnectionState::kConnected) {
      self->GetOverlay();
      self->MeasureClock();
    } else if (state == net::ConnectionState::kDisconnected) {
      spdlog::warn("the window's live video: {}", why);
    }
  });
  video::LiveRequest request;
  request.set_fps(impl->options.fps);
  request.set_encoding(video::RAW);
  impl->client->Subscribe<video::LiveFrame>(
      "igms.video.VideoService.Live", request,
      [weak](const video::LiveFrame& f) {
        if (auto self = weak.lock()) self->OnFrame(f);
      },
      [](const net::Status& s) { spdlog::warn("the live video stream: {}", s.ToString()); });
  impl->client->Start();
  impl->thread = std::thread([impl = impl.get()] { impl->io.run(); });
  return std::unique_ptr<LiveVideo>(new LiveVideo(std::move(impl)));
}

LiveVideo::LiveVideo(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}

LiveVideo::~LiveVideo() {
  boost::asio::post(impl_->io, [impl = impl_.get()] { impl->client->Stop(); });
  impl_->work.reset();
  impl_->io.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
  impl_->client.reset();
}

std::optional<StereoFrame> LiveVideo::Newer(uint64_t after) const {
  std::lock_guard lock(impl_->mutex);
  if (impl_->newest.sequence == 0 || impl_->newest.sequence == after) return std::nullopt;
  return impl_->newest;
}

bool LiveVideo::lost() const {
  std::lock_guard lock(impl_->mutex);
  if (!impl_->connected) return true;
  const auto stale =
      std::chrono::duration_cast<std::chrono::nanoseconds>(impl_->options.stale_after).count();
  return MonotonicNs() - impl_->last_frame_ns > stale;
}

LiveStats LiveVideo::stats() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->stats;
}

video::OverlaySettings LiveVideo::overlay() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->overlay;
}

void LiveVideo::MoveOffset(int du, int dv) {
  video::SetOverlayRequest request;
  {
    std::lock_guard lock(impl_->mutex);
    impl_->overlay.set_u_offset_px(impl_->overlay.u_offset_px() + du);
    impl_->overlay.set_v_offset_px(impl_->overlay.v_offset_px() + dv);
    *request.mutable_settings() = impl_->overlay;
  }
  boost::asio::post(impl_->io, [self = impl_, request] {
    self->client->Call<video::SetOverlayResponse>(
        "igms.video.VideoService.SetOverlay", request, std::chrono::milliseconds(2000),
        [self](const net::Result<video::SetOverlayResponse>& r) {
          if (!r.ok()) {
            spdlog::warn("VideoService.SetOverlay: {}", r.status.ToString());
            return;
          }
          std::lock_guard lock(self->mutex);
          self->overlay = r.value.settings();
        });
  });
}

void LiveVideo::FetchGrab(uint64_t frame_id) {
  {
    std::lock_guard lock(impl_->mutex);
    if (impl_->grab_id == frame_id) return;
    impl_->grab_id = frame_id;
    impl_->grab.reset();
  }
  video::GetImagesRequest request;
  request.set_frame_id(frame_id);
  request.set_side(video::BOTH);
  request.set_encoding(video::RAW);
  boost::asio::post(impl_->io, [self = impl_, request] {
    self->client->Call<video::GetImagesResponse>(
        "igms.video.VideoService.GetImages", request, std::chrono::milliseconds(5000),
        [self, id = request.frame_id()](const net::Result<video::GetImagesResponse>& r) {
          if (!r.ok()) {
            spdlog::warn("the grabbed pair {}: {}", id, r.status.ToString());
            std::lock_guard lock(self->mutex);
            if (self->grab_id == id) self->grab_id = 0;  // asked again on the next frame
            return;
          }
          StereoFrame frame;
          frame.left = wire::DecodeProtoImage(r.value.left());
          frame.right = wire::DecodeProtoImage(r.value.right());
          if (frame.left.empty() || frame.right.empty()) return;
          frame.sequence = kGrabSequence + id;
          frame.capture_unix_ns = r.value.left_capture_unix_ns();
          frame.joints.assign(r.value.pose().joints_rad().begin(),
                              r.value.pose().joints_rad().end());
          std::lock_guard lock(self->mutex);
          if (self->grab_id == id) self->grab = std::move(frame);
        });
  });
}

std::optional<StereoFrame> LiveVideo::Grabbed(uint64_t frame_id) const {
  std::lock_guard lock(impl_->mutex);
  if (impl_->grab_id != frame_id) return std::nullopt;
  return impl_->grab;
}

}  // namespace igms::control
