#include "object_server/object_service.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "common/net/process_server.h"
#include "common/wire/image_message.h"
#include "igms/video.pb.h"

namespace igms::object {

config::Keys ObjectKeys(ObjectServiceOptions* options) {
  config::Keys keys = net::ServerKeys();
  keys.Bind("fetch_timeout_ms", &options->fetch_timeout, "one GetImages call to the video server");
  keys.Bind("cache_frames", &options->cache_frames, "grabs' images kept");
  keys.Bind("workers", &options->workers, "locates run at once");
  keys.Bind("camera_blur_px", &options->locate.camera_blur_px,
            "the cameras' blur in pixels, for the silhouette fit");
  keys.Bind("floor_height", &options->locate.floor_height,
            "the height (world z) of the floor the site's objects stand on; none: no floor known");
  keys.Bind("video", &options->video_process, "the video server process it fetches frames from");
  return keys;
}
namespace {

using Clock = std::chrono::steady_clock;
const std::string kGetImages = "igms.video.VideoService.GetImages";

void SetVec(const Eigen::Vector3d& v, igms::object::Vec3* out) {
  out->set_x(v.x());
  out->set_y(v.y());
  out->set_z(v.z());
}

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

}  // namespace

bool ObjectServiceOptions::Check(std::string* error) const {
  if (fetch_timeout.count() <= 0) {
    *error = "fetch_timeout_ms must be positive";
    return false;
  }
  if (cache_frames == 0) {
    *error = "cache_frames must be at least 1";
    return false;
  }
  if (max_queue == 0) {
    *error = "max_queue must be at least 1";
    return false;
  }
  if (workers < 1 || workers > 64) {
    *error = "workers must be in 1..64";
    return false;
  }
  return locate.Check(error);
}

net::Status ValidateLocateRequest(const igms::object::LocateRequest& request) {
  if (request.type() != igms::object::OBJECT_TYPE_CYLINDER &&
      request.type() != igms::object::OBJECT_TYPE_BOX) {
    return net::Status::Error(igms::BAD_REQUEST,
                              "type must be OBJECT_TYPE_CYLINDER or OBJECT_TYPE_BOX, not " +
                                  std::to_string(request.type()));
  }
  if (request.marks_size() != 4) {
    return net::Status::Error(igms::BAD_REQUEST, "exactly four marks are needed, got " +
                                                     std::to_string(request.marks_size()));
  }
  for (int i = 0; i < 4; ++i) {
    const auto& m = request.marks(i);
    if (!std::isfinite(m.x()) || !std::isfinite(m.y()) || !std::isfinite(m.z())) {
      return net::Status::Error(igms::BAD_REQUEST,
                                "mark " + std::to_string(i + 1) + " is not three finite numbers");
    }
  }
  if (!std::isfinite(request.range()) || request.range() < 0) {
    return net::Status::Error(igms::BAD_REQUEST, "range must be finite and not negative");
  }
  for (int i = 0; i < request.known_size(); ++i) {
    std::string why;
    if (!KnownFromProto(request.known(i), &why))
      return net::Status::Error(igms::BAD_REQUEST, "known solid " + std::to_string(i + 1) + " (" +
                                                       request.known(i).name() + "): " + why);
  }
  return net::Status::Ok();
}

std::optional<KnownShape> KnownFromProto(const igms::object::KnownSolid& k, std::string* why) {
  const auto vec = [](const igms::object::Vec3& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); };
  // As the locator's result it was, then as every found result becomes a known solid.
  LocateResult r;
  if (k.type() == igms::object::OBJECT_TYPE_CYLINDER) {
    const auto& c = k.cylinder();
    const Eigen::Vector3d axis = vec(c.axis());
    if (!(axis.norm() > 1e-9) || !(c.radius() > 0) || !(c.height() > 0)) {
      *why = "a cylinder needs an axis, a positive radius and a positive height";
      return std::nullopt;
    }
    r.type = SolidType::kCylinder;
    r.cylinder.center = vec(c.center());
    r.cylinder.axis = axis.normalized();
    r.cylinder.radius = c.radius();
    r.cylinder.height = c.height();
    r.cylinder.center_sigma = vec(c.center_sigma()).cwiseAbs();
    r.cylinder.radius_sigma = std::abs(c.radius_sigma());
  } else if (k.type() == igms::object::OBJECT_TYPE_BOX) {
    const auto& b = k.box();
    if (!(vec(b.size()).minCoeff() > 0)) {
      *why = "a box needs a positive size";
      return std::nullopt;
    }
    r.type = SolidType::kBox;
    r.box.center = vec(b.center());
    r.box.size = vec(b.size());
    r.box.yaw_deg = b.yaw_deg();
    r.box.center_sigma = vec(b.center_sigma()).cwiseAbs();
    r.box.size_sigma = vec(b.size_sigma()).cwiseAbs();
  } else {
    *why = "type must be OBJECT_TYPE_CYLINDER or OBJECT_TYPE_BOX";
    return std::nullopt;
  }
  KnownShape out = KnownFromResult(r, k.name());
  if (!out.params.allFinite() || !std::isfinite(out.sigma)) {
    *why = "not finite numbers";
    return std::nullopt;
  }
  return out;
}

void ResultToProto(const LocateResult& r, igms::object::LocateResponse* out) {
  out->set_found(r.found);
  out->set_type(r.type == SolidType::kCylinder ? igms::object::OBJECT_TYPE_CYLINDER
                                               : igms::object::OBJECT_TYPE_BOX);
  out->set_reason(static_cast<igms::object::FailureReason>(static_cast<int>(r.reason)));
  out->set_detail(r.detail);
  if (r.found && r.type == SolidType::kCylinder) {
    auto* c = out->mutable_cylinder();
    SetVec(r.cylinder.center, c->mutable_center());
    SetVec(r.cylinder.axis, c->mutable_axis());
    c->set_radius(r.cylinder.radius);
    c->set_height(r.cylinder.height);
    SetVec(r.cylinder.center_sigma, c->mutable_center_sigma());
    c->set_radius_sigma(r.cylinder.radius_sigma);
    c->set_height_sigma(r.cylinder.height_sigma);
  } else if (r.found) {
    auto* b = out->mutable_box();
    SetVec(r.box.min, b->mutable_min());
    SetVec(r.box.max, b->mutable_max());
    SetVec(r.box.min_sigma, b->mutable_min_sigma());
    SetVec(r.box.max_sigma, b->mutable_max_sigma());
    SetVec(r.box.center, b->mutable_center());
    SetVec(r.box.size, b->mutable_size());
    b->set_yaw_deg(r.box.yaw_deg);
    SetVec(r.box.center_sigma, b->mutable_center_sigma());
    SetVec(r.box.size_sigma, b->mutable_size_sigma());
    b->set_yaw_sigma_deg(r.box.yaw_sigma_deg);
    b->set_texture_u0(r.box.texture_rect.x);
    b->set_texture_v0(r.box.texture_rect.y);
    b->set_texture_u1(r.box.texture_rect.x + r.box.texture_rect.width - 1);
    b->set_texture_v1(r.box.texture_rect.y + r.box.texture_rect.height - 1);
    std::vector<uint8_t> png;
    if (!r.box.texture.empty() &&
        cv::imencode(".png", r.box.texture, png, {cv::IMWRITE_PNG_COMPRESSION, 1}))
      b->set_texture_png(png.data(), png.size());
  }
  out->set_boundary_pixels(r.boundary_pixels);
  out->set_ssd_rms(r.ssd_rms);
  out->set_outline_samples(r.outline_samples);
  out->set_rms_left_px(r.rms_left_px);
  out->set_rms_right_px(r.rms_right_px);
  out->set_locate_ms(r.elapsed_ms);
  if (r.range.used) {
    auto* range = out->mutable_range();
    range->set_used(true);
    range->set_constrained(r.range.constrained);
    range->set_measured(r.range.measured);
    range->set_expected_min(r.range.expected_min);
    range->set_expected_max(r.range.expected_max);
    range->set_agrees(r.range.agrees);
    range->set_detail(r.range.detail);
  }
}

geometry::ProjectiveCamera CameraAtPose(const geometry::ProjectiveCamera& camera,
                                        const geometry::PlatformModel& platform,
                                        std::span<const double> joints_rad) {
  const geometry::Matrix34 P = geometry::CameraAtPose(camera.P(), platform, joints_rad);
  return camera.lens() ? geometry::ProjectiveCamera(P, camera.image_size(), *camera.lens())
                       : geometry::ProjectiveCamera(P, camera.image_size());
}

ObjectService::ObjectService(net::Client& video, geometry::ProjectiveCamera left,
                             geometry::ProjectiveCamera right, ObjectServiceOptions options)
    : video_(video),
      left_camera_(std::move(left)),
      right_camera_(std::move(right)),
      options_(std::move(options)) {
  // A fetch while the video server is down fails at once (VideoUp) rather than waiting out
  // fetch_timeout for a connection the client retries in the background.
  if (video_.connected()) link_->state = net::ConnectionState::kConnected;
  video_.OnStateChange([link = link_](net::ConnectionState state, const std::string& reason) {
    {
      std::lock_guard lock(link->mutex);
      link->state = state;
      link->reason = reason;
    }
    link->changed.notify_all();
  });
  for (int i = 0; i < options_.workers; ++i) workers_.emplace_back([this] { Work(); });
}

ObjectService::~ObjectService() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  for (auto& w : workers_) w.join();
}

void ObjectService::Register(net::Server& server) {
  using igms::object::LocateRequest;
  using igms::object::LocateResponse;
  server.Handle<igms::object::StatusRequest, igms::object::StatusResponse>(
      "igms.object.ObjectService.Status",
      [this](const igms::object::StatusRequest&, igms::object::StatusResponse& out) {
        out.set_calibration_file(options_.calibration_file);
        out.set_calibration_sha256(options_.calibration_sha256);
        out.set_calibration_has_platform(options_.platform.has_value());
        out.set_calibration_has_ranger(options_.ranger_mount.has_value());
        out.set_video(options_.video);
        out.set_video_connected(video_.connected());
        if (!out.video_connected()) {
          std::lock_guard lock(link_->mutex);
          out.set_video_detail(link_->reason);
        }
        out.set_fetch_timeout_ms(static_cast<uint32_t>(options_.fetch_timeout.count()));
        return net::Status::Ok();
      });
  server.HandleAsync<LocateRequest, LocateResponse>(
      "igms.object.ObjectService.Locate",
      [this](const LocateRequest& request, net::Reply<LocateResponse> reply) {
        if (net::Status bad = ValidateLocateRequest(request); !bad.ok()) {
          reply(bad);
          return;
        }
        std::unique_lock lock(mutex_);
        if (stopping_ || queue_.size() >= options_.max_queue) {
          const bool stopping = stopping_;
          lock.unlock();
          reply(stopping ? net::Status::Error(igms::SHUTTING_DOWN, "the object server is stopping")
                         : net::Status::Error(igms::UNAVAILABLE,
                                              "the object server is busy; try again shortly"));
          return;
        }
        queue_.push_back([this, request, reply](bool run) {
          if (run) {
            Run(request, reply);
          } else {
            reply(net::Status::Error(igms::SHUTTING_DOWN, "the object server is stopping"));
          }
        });
        lock.unlock();
        wake_.notify_one();
      });
}

void ObjectService::Work() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (stopping_) {
      for (auto& job : queue_) job(false);
      queue_.clear();
      return;
    }
    Job job = std::move(queue_.front());
    queue_.pop_front();
    lock.unlock();
    job(true);
    lock.lock();
  }
}

net::Status ObjectService::Fetch(uint64_t frame_id, Frame* frame, double* fetch_ms) {
  {
    std::lock_guard lock(cache_mutex_);
    for (auto it = cache_.begin(); it != cache_.end(); ++it) {
      if (it->id != frame_id) continue;
      cache_.splice(cache_.begin(), cache_, it);
      *frame = cache_.front();  // the images' pixels are shared, not copied
      *fetch_ms = 0;
      return net::Status::Ok();
    }
  }
  // Fetched without the lock, so a cached frame's locate need not wait for this one; two
  // workers wanting the same new frame may both fetch it, and the cache keeps one.
  const auto start = Clock::now();
  if (std::string why; !VideoUp(&why)) {
    *fetch_ms = Ms(Clock::now() - start);
    return net::Status::Error(igms::UNAVAILABLE, "cannot fetch frame " + std::to_string(frame_id) +
                                                     ": the video server at " + options_.video +
                                                     " is not connected: " + why);
  }
  igms::video::GetImagesRequest request;
  request.set_frame_id(frame_id);
  request.set_side(igms::video::BOTH);
  request.set_encoding(igms::video::RAW);  // loopback: no time spent compressing
  auto got =
      video_.CallSync<igms::video::GetImagesResponse>(kGetImages, request, options_.fetch_timeout);
  *fetch_ms = Ms(Clock::now() - start);
  if (!got.ok()) {
    if (got.status.code == igms::NOT_FOUND) {
      return net::Status::Error(igms::NOT_FOUND, "the video server does not hold frame " +
                                                     std::to_string(frame_id) + ": " +
                                                     got.status.message);
    }
    return net::Status::Error(igms::UNAVAILABLE, "cannot fetch frame " + std::to_string(frame_id) +
                                                     " from the video server at " + options_.video +
                                                     ": " + got.status.message);
  }
  Frame fetched;
  fetched.id = frame_id;
  fetched.left = wire::DecodeProtoImage(got.value.left());
  fetched.right = wire::DecodeProtoImage(got.value.right());
  fetched.joints_rad.assign(got.value.pose().joints_rad().begin(),
                            got.value.pose().joints_rad().end());
  if (fetched.left.empty() || fetched.right.empty()) {
    return net::Status::Error(igms::UNAVAILABLE, "the video server sent frame " +
                                                     std::to_string(frame_id) +
                                                     " with images that do not decode");
  }
  {
    std::lock_guard lock(cache_mutex_);
    if (std::none_of(cache_.begin(), cache_.end(),
                     [&](const Frame& f) { return f.id == frame_id; }))
      cache_.push_front(fetched);
    while (cache_.size() > options_.cache_frames) cache_.pop_back();
  }
  *frame = std::move(fetched);
  return net::Status::Ok();
}

bool ObjectService::VideoUp(std::string* why) {
  if (video_.connected()) return true;
  std::unique_lock lock(link_->mutex);
  link_->changed.wait_for(lock, options_.fetch_timeout,
                          [this] { return link_->state != net::ConnectionState::kConnecting; });
  if (video_.connected()) return true;
  *why = link_->state == net::ConnectionState::kConnecting
             ? "no connection within " + std::to_string(options_.fetch_timeout.count()) + " ms"
             : link_->reason;
  return false;
}

void MarksToProto(const std::array<Eigen::Vector3d, 4>& marks,
                  igms::object::LocateRequest* request) {
  for (const auto& m : marks) {
    auto* v = request->add_marks();
    v->set_x(m.x());
    v->set_y(m.y());
    v->set_z(m.z());
  }
}

void ObjectService::Run(const igms::object::LocateRequest& request,
                        net::Reply<igms::object::LocateResponse> reply) {
  Frame frame;
  double fetch_ms = 0;
  if (net::Status status = Fetch(request.frame_id(), &frame, &fetch_ms); !status.ok()) {
    spdlog::warn("locate on frame {}: {}", request.frame_id(), status.message);
    reply(status);
    return;
  }
  LocateInput input;
  input.type =
      request.type() == igms::object::OBJECT_TYPE_CYLINDER ? SolidType::kCylinder : SolidType::kBox;
  for (int i = 0; i < 4; ++i) {
    const auto& m = request.marks(i);
    input.marks[i] = Eigen::Vector3d(m.x(), m.y(), m.z());
  }
  for (const auto& k : request.known()) {
    std::string why;
    if (auto known = KnownFromProto(k, &why)) input.known.push_back(std::move(*known));
  }
  input.left = frame.left;
  input.right = frame.right;
  input.left_camera = left_camera_;
  input.right_camera = right_camera_;
  std::optional<RangerPose> ranger = options_.ranger;
  const bool posed = std::any_of(frame.joints_rad.begin(), frame.joints_rad.end(),
                                 [](double q) { return q != 0.0; });
  if (posed && options_.platform && frame.joints_rad.size() == options_.platform->joints.size()) {
    input.left_camera = CameraAtPose(left_camera_, *options_.platform, frame.joints_rad);
    input.right_camera = CameraAtPose(right_camera_, *options_.platform, frame.joints_rad);
    if (options_.ranger_mount) {
      ranger = geometry::RangerBeamAt(options_.ranger_mount->origin, options_.ranger_mount->axis,
                                      options_.platform, frame.joints_rad);
    }
  } else if (posed) {
    spdlog::warn(
        "frame {} was grabbed at a platform pose the calibration has no model for; "
        "locating it at the zero pose",
        request.frame_id());
  }
  if (request.range() > 0 && ranger) {
    input.range = request.range();
    input.ranger_origin = ranger->origin;
    input.ranger_axis = ranger->axis;
  }
  const LocateResult result = Locate(input, options_.locate);
  igms::object::LocateResponse response;
  ResultToProto(result, &response);
  if (request.range() > 0 && !options_.ranger) {
    auto* range = response.mutable_range();
    range->set_measured(request.range());
    range->set_detail("the range was not used: the object server's calibration has no ranger map");
  }
  response.set_fetch_ms(fetch_ms);
  spdlog::info("locate {} on frame {}: {} ({:.0f} ms locate, {:.0f} ms fetch)",
               input.type == SolidType::kCylinder ? "cylinder" : "box", request.frame_id(),
               result.found ? "found" : FailureName(result.reason), result.elapsed_ms, fetch_ms);
  reply(net::Status::Ok(), response);
}

}  // namespace igms::object
