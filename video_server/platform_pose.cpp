#include "video_server/platform_pose.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <exception>

#include "common/calibration/calibration_file.h"
#include "video_server/video_config.h"

namespace igms::video {

PoseStamp PoseFromPlatformState(const devices::PlatformState& state,
                                const std::optional<geometry::PlatformModel>& model) {
  PoseStamp pose;
  pose.from_platform = true;
  pose.time_unix_ns = state.stamp().receive_unix_ns();
  const double ticks[3] = {static_cast<double>(state.yaw_ticks()),
                           static_cast<double>(state.pitch_ticks()),
                           static_cast<double>(state.roll_ticks())};
  if (model) {
    for (size_t i = 0; i < 3; ++i) {
      pose.joints_rad[i] =
          i < model->joints.size() ? ticks[i] * model->joints[i].radians_per_tick : 0.0;
    }
  } else {
    constexpr double kRad = M_PI / 180.0;
    pose.joints_rad = {state.yaw_deg() * kRad, state.pitch_deg() * kRad, state.roll_deg() * kRad};
  }
  return pose;
}

Result<std::optional<PlatformFollowOptions>> ConfiguredPlatformFollow(
    const config::ProcessOptions& process) {
  const std::string name = ReadVideoConfig(process).platform;
  if (name.empty()) return std::optional<PlatformFollowOptions>();
  PlatformFollowOptions options;
  options.process = name;
  options.client.name = process.name;
  options.client.token = process.lab.token;
  options.client.host = process.HostOf(name);
  try {
    options.client.port = process.PortOf(name);
  } catch (const std::exception& e) {
    return ErrorMessage{process.Key("platform") + " names '" + name + "': " + e.what()};
  }
  // A model mismatch is better found at start than as a wrong pose later.
  if (!process.lab.calibration.empty()) {
    const auto calibration = calibration::LoadCalibration(process.lab.calibration);
    if (!calibration.ok()) return ErrorMessage{"lab.calibration: " + calibration.error()};
    options.model = calibration->platform;
  }
  return std::optional<PlatformFollowOptions>(std::move(options));
}

PlatformPoseFollower::PlatformPoseFollower(boost::asio::io_context& io,
                                           PlatformFollowOptions options)
    : options_(std::move(options)), client_(io, options_.client) {}

PlatformPoseFollower::~PlatformPoseFollower() { Stop(); }

void PlatformPoseFollower::Start() {
  client_.OnStateChange([this](net::ConnectionState state, const std::string& reason) {
    OnConnection(state, reason);
  });
  client_.Start();
  client_.Subscribe<devices::PlatformState>(
      "igms.devices.PlatformService.Live", devices::SubscribeRequest(),
      [this](const devices::PlatformState& state) { OnReading(state); });
}

void PlatformPoseFollower::Stop() { client_.Stop(); }

PoseStamp PlatformPoseFollower::Pose() const {
  std::lock_guard lock(mutex_);
  return pose_;
}

uint64_t PlatformPoseFollower::readings() const {
  std::lock_guard lock(mutex_);
  return readings_;
}

void PlatformPoseFollower::OnReading(const devices::PlatformState& state) {
  const PoseStamp pose = PoseFromPlatformState(state, options_.model);
  std::lock_guard lock(mutex_);
  pose_ = pose;
  ++readings_;
}

void PlatformPoseFollower::OnConnection(net::ConnectionState state, const std::string& reason) {
  const std::string where = "platform daemon '" + options_.process + "' at " +
                            options_.client.host + ":" + std::to_string(options_.client.port);
  std::lock_guard lock(mutex_);
  if (state == net::ConnectionState::kConnected) {
    if (reported_loss_ || !ever_connected_) spdlog::info("following the {}", where);
    reported_loss_ = false;
    ever_connected_ = true;
  } else if (state == net::ConnectionState::kDisconnected && !reported_loss_) {
    reported_loss_ = true;
    if (pose_.from_platform) {
      spdlog::warn(
          "lost the {} ({}); grabs go on at the last known pose ({:.4f}, {:.4f}, "
          "{:.4f} rad) while it reconnects",
          where, reason, pose_.joints_rad[0], pose_.joints_rad[1], pose_.joints_rad[2]);
    } else {
      spdlog::warn("no {} ({}); grabs go on at the zero pose while it reconnects", where, reason);
    }
  }
}

}  // namespace igms::video
