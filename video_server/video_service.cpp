#include "video_server/video_service.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <chrono>
#include <stdexcept>

#include "video_server/proto_convert.h"

namespace igms::video {
namespace {

using Clock = std::chrono::steady_clock;

std::string HostName() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "";
  return name;
}
constexpr uint32_t kDefaultEdgeWaitMs = 10000;
constexpr uint32_t kMaxEdgeWaitMs = 120000;

net::Status NotFound(const FrameLookup& lookup) {
  return net::Status::Error(igms::NOT_FOUND, lookup.error);
}

// The rectangle a request names, checked against the frame's size.
std::optional<cv::Rect> RequestRect(const igms::video::Region& region, cv::Size size,
                                    net::Status* status) {
  auto rect = wire::ResolveRegion(wire::RegionFromProto(region), size);
  if (!rect.ok()) {
    *status = net::Status::Error(igms::BAD_REQUEST, rect.error());
    return std::nullopt;
  }
  return *rect;
}

bool ValidSide(Side side) { return side == BOTH || side == LEFT || side == RIGHT; }

void FillEdgeMap(const EdgeImage& edges, const cv::Rect& rect, wire::ImageEncoding encoding,
                 EdgeMap* out) {
  wire::EncodeRegion(edges.edges, rect, encoding, out->mutable_edges());
  const std::vector<float> directions = DirectionsInRegion(edges, rect);
  out->mutable_direction_rad()->Assign(directions.begin(), directions.end());
  out->set_edge_count(static_cast<int>(directions.size()));
}

}  // namespace

bool VideoServiceOptions::Check(std::string* error) const {
  if (store_capacity < 1 || store_capacity > 10000) {
    *error = "store capacity must be 1..10000";
    return false;
  }
  if (edge_threads < 1 || edge_threads > 64) {
    *error = "edge threads must be 1..64";
    return false;
  }
  if (encode_threads < 1 || encode_threads > 64) {
    *error = "encode threads must be 1..64";
    return false;
  }
  return edges.Check(error);
}

VideoService::VideoService(boost::asio::io_context& io, std::unique_ptr<CaptureBackend> backend,
                           VideoServiceOptions options, Overlay overlay, PoseSource pose)
    : io_(io),
      options_(std::move(options)),
      backend_(std::move(backend)),
      pose_(std::move(pose)),
      store_(options_.store_capacity, ids_.first()),
      overlay_(options_.overlay_path, overlay),
      encode_pool_(options_.encode_threads),
      pipeline_(options_.edges, options_.edge_threads),
      capture_pool_(1),
      live_([this] { return CaptureNow(); }) {
  if (std::string problem; !options_.Check(&problem)) {
    throw std::invalid_argument(problem);
  }
  if (!backend_) throw std::invalid_argument("the video service needs a capture backend");
}

VideoService::~VideoService() = default;

CaptureResult VideoService::CaptureNow() {
  const PoseStamp pose = pose_ ? pose_() : PoseStamp{};
  std::lock_guard lock(backend_mutex_);
  return backend_->Capture(pose);
}

net::Status VideoService::Grab(GrabResponse& response) {
  const auto start = Clock::now();
  CaptureResult captured = CaptureNow();
  const double capture_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  if (!captured.ok()) {
    spdlog::warn("grab failed: {}", captured.error);
    return net::Status::Error(igms::UNAVAILABLE, "grab failed: " + captured.error);
  }
  // Ids must enter the store in order, whichever threads grab.
  std::shared_ptr<FrameRecord> record;
  uint64_t id = 0;
  {
    std::lock_guard lock(insert_mutex_);
    id = ids_.Next();
    record = store_.Insert(id, std::move(*captured.images));
  }
  pipeline_.Start(record);
  ++grabs_;
  const StereoImages& images = record->images();
  response.set_frame_id(id);
  response.set_left_capture_unix_ns(images.left_capture_unix_ns);
  response.set_right_capture_unix_ns(images.right_capture_unix_ns);
  ToProto(images.pose, response.mutable_pose());
  response.set_width(images.left.cols);
  response.set_height(images.left.rows);
  response.set_channels(images.left.channels());
  response.set_capture_ms(capture_ms);
  return net::Status::Ok();
}

net::Status VideoService::GetImages(const GetImagesRequest& request, GetImagesResponse& response) {
  if (!ValidSide(request.side())) return net::Status::Error(igms::BAD_REQUEST, "unknown side");
  FrameLookup lookup = store_.Find(request.frame_id());
  if (!lookup.record) return NotFound(lookup);
  const StereoImages& images = lookup.record->images();
  net::Status status;
  auto rect = RequestRect(request.region(), images.left.size(), &status);
  if (!rect) return status;
  const wire::ImageEncoding encoding =
      wire::EncodingFromProto(request.encoding(), options_.default_encoding);
  response.set_frame_id(request.frame_id());
  if (request.side() != RIGHT) {
    wire::EncodeRegion(images.left, *rect, encoding, response.mutable_left());
  }
  if (request.side() != LEFT) {
    wire::EncodeRegion(images.right, *rect, encoding, response.mutable_right());
  }
  response.set_left_capture_unix_ns(images.left_capture_unix_ns);
  response.set_right_capture_unix_ns(images.right_capture_unix_ns);
  ToProto(images.pose, response.mutable_pose());
  return net::Status::Ok();
}

void VideoService::GetEdges(const GetEdgesRequest& request,
                            std::function<void(const net::Status&, const GetEdgesResponse&)> done) {
  if (!ValidSide(request.side())) {
    done(net::Status::Error(igms::BAD_REQUEST, "unknown side"), {});
    return;
  }
  if (request.timeout_ms() > kMaxEdgeWaitMs) {
    done(net::Status::Error(igms::BAD_REQUEST, "timeout_ms must be at most 120000"), {});
    return;
  }
  FrameLookup lookup = store_.Find(request.frame_id());
  if (!lookup.record) {
    done(NotFound(lookup), {});
    return;
  }
  net::Status status;
  auto rect = RequestRect(request.region(), lookup.record->images().left.size(), &status);
  if (!rect) {
    done(status, {});
    return;
  }
  // Whichever comes first, the edges or the timer, answers; the other finds it done. The
  // timer lives on a strand, so arming and cancelling it never race whatever thread the
  // edges arrive on.
  struct Pending {
    explicit Pending(boost::asio::io_context& io)
        : strand(boost::asio::make_strand(io)), timer(strand) {}
    std::atomic<bool> answered{false};
    std::function<void(const net::Status&, const GetEdgesResponse&)> done;
    boost::asio::strand<boost::asio::io_context::executor_type> strand;
    boost::asio::steady_timer timer;
  };
  auto pending = std::make_shared<Pending>(io_);
  pending->done = std::move(done);
  const uint32_t wait_ms = request.timeout_ms() ? request.timeout_ms() : kDefaultEdgeWaitMs;
  boost::asio::post(pending->strand, [pending, id = request.frame_id(), wait_ms] {
    if (pending->answered) return;
    pending->timer.expires_after(std::chrono::milliseconds(wait_ms));
    pending->timer.async_wait([pending, id, wait_ms](const boost::system::error_code& ec) {
      if (ec || pending->answered.exchange(true)) return;
      pending->done(net::Status::Error(igms::TIMEOUT, "edges of frame " + std::to_string(id) +
                                                          " not ready within " +
                                                          std::to_string(wait_ms) + " ms"),
                    {});
    });
  });
  const wire::ImageEncoding encoding =
      wire::EncodingFromProto(request.encoding(), options_.default_encoding);
  const Side side = request.side();
  const uint64_t id = request.frame_id();
  const cv::Rect region = *rect;
  lookup.record->OnEdgesReady(
      [this, pending, encoding, side, id, region](const std::shared_ptr<const StereoEdges>& edges) {
        encode_pool_.Post([pending, edges, encoding, side, id, region] {
          if (pending->answered.exchange(true)) return;
          boost::asio::post(pending->strand, [pending] { pending->timer.cancel(); });
          if (!edges->error.empty()) {
            pending->done(net::Status::Error(igms::INTERNAL, edges->error), {});
            return;
          }
          GetEdgesResponse response;
          response.set_frame_id(id);
          if (side != RIGHT) FillEdgeMap(edges->left, region, encoding, response.mutable_left());
          if (side != LEFT) FillEdgeMap(edges->right, region, encoding, response.mutable_right());
          ToProto(edges->options, response.mutable_parameters());
          response.set_ready_ms(edges->ready_ms);
          response.set_left_ms(edges->left_ms);
          response.set_right_ms(edges->right_ms);
          pending->done(net::Status::Ok(), response);
        });
      });
}

net::Status VideoService::SetOverlay(const SetOverlayRequest& request,
                                     SetOverlayResponse& response) {
  std::string error;
  if (!overlay_.Set(FromProto(request.settings()), &error)) {
    std::string problem;
    const bool invalid = !FromProto(request.settings()).Check(&problem);
    return net::Status::Error(invalid ? igms::BAD_REQUEST : igms::INTERNAL, error);
  }
  ToProto(overlay_.Get(), response.mutable_settings());
  spdlog::info("overlay set: u {} v {} key {}", request.settings().u_offset_px(),
               request.settings().v_offset_px(), request.settings().key_level());
  return net::Status::Ok();
}

StatusResponse VideoService::Status() const {
  StatusResponse status;
  status.set_backend(backend_->Describe());
  status.set_frames_held(static_cast<uint32_t>(store_.size()));
  status.set_capacity(static_cast<uint32_t>(store_.capacity()));
  status.set_evictions(store_.evictions());
  status.set_bytes_held(store_.bytes());
  status.set_grabs(grabs_.load());
  if (auto newest = store_.Newest()) status.set_newest_frame_id(newest->id());
  status.set_live_subscribers(static_cast<uint32_t>(live_.subscribers()));
  ToProto(options_.edges, status.mutable_edge_parameters());
  status.set_calibration_file(options_.calibration_file);
  status.set_calibration_sha256(options_.calibration_sha256);
  // Where edges are computed, so an operator of a lab over several hosts can tell.
  static const std::string hostname = HostName();
  status.set_hostname(hostname);
  if (server_ && server_->port() != 0) {
    status.set_listen_address(server_->options().bind_address + ":" +
                              std::to_string(server_->port()));
  }
  const EdgeJobCounts jobs = pipeline_.Counts();
  status.set_edge_jobs_done(jobs.done);
  status.set_edge_jobs_failed(jobs.failed);
  status.set_edge_jobs_skipped(jobs.skipped);
  status.set_edge_jobs_in_flight(static_cast<uint32_t>(jobs.in_flight));
  return status;
}

void VideoService::Register(net::Server& server) {
  server_ = &server;
  const std::string prefix = "igms.video.VideoService.";
  server.HandleAsync<GrabRequest, GrabResponse>(
      prefix + "Grab", [this](const GrabRequest&, net::Reply<GrabResponse> reply) {
        capture_pool_.Post([this, reply] {
          GrabResponse response;
          net::Status status = Grab(response);
          reply(status, response);
        });
      });
  server.HandleAsync<GetImagesRequest, GetImagesResponse>(
      prefix + "GetImages",
      [this](const GetImagesRequest& request, net::Reply<GetImagesResponse> reply) {
        encode_pool_.Post([this, request, reply] {
          GetImagesResponse response;
          net::Status status = GetImages(request, response);
          reply(status, response);
        });
      });
  server.HandleAsync<GetEdgesRequest, GetEdgesResponse>(
      prefix + "GetEdges",
      [this](const GetEdgesRequest& request, net::Reply<GetEdgesResponse> reply) {
        GetEdges(request, [reply](const net::Status& status, const GetEdgesResponse& response) {
          reply(status, response);
        });
      });
  server.Handle<GetOverlayRequest, GetOverlayResponse>(
      prefix + "GetOverlay", [this](const GetOverlayRequest&, GetOverlayResponse& response) {
        ToProto(overlay_.Get(), response.mutable_settings());
        return net::Status::Ok();
      });
  server.Handle<SetOverlayRequest, SetOverlayResponse>(
      prefix + "SetOverlay",
      [this](const SetOverlayRequest& request, SetOverlayResponse& response) {
        return SetOverlay(request, response);
      });
  server.Handle<StatusRequest, StatusResponse>(
      prefix + "GetStatus", [this](const StatusRequest&, StatusResponse& response) {
        response = Status();
        return net::Status::Ok();
      });
  server.HandleStream<LiveRequest, LiveFrame>(
      prefix + "Live",
      [this](const LiveRequest& request,
             const std::shared_ptr<net::Publisher<LiveFrame>>& publisher) {
        std::string error = live_.Add(
            request, [publisher](const LiveFrame& frame) { return publisher->Send(frame); });
        if (!error.empty()) return net::Status::Error(igms::BAD_REQUEST, error);
        return net::Status::Ok();
      },
      /*latest_only=*/true);
}

}  // namespace igms::video
