// The camera platform's pose as the video server knows it: the latest orientation
// igms-platformd reports reaching, followed over the daemon's reading stream.
//
// Configuration (processes.NAME of the lab configuration, docs/protocol-video.md):
//
//   video:
//     platform: platform     # the lab process whose stream to follow; absent = no platform
//
// When the video section names a platform process, the server subscribes to
// igms.devices.PlatformService.Live at that process's host and port (the lab token, a client
// that reconnects by itself) and keeps the newest PlatformState. Each grab is stamped with it:
// from_platform true, time_unix_ns the daemon's receive time of that reading. The joint
// angles (radians, pan, tilt, roll) are the reported encoder ticks times the calibration's
// platform model's tick scales when lab.calibration has a `platform` map (so the pose and the
// model that moves the cameras agree), otherwise the daemon's degrees converted to radians.
//
// Absent or vanished daemon: grabs never wait for it. Before the first reading the pose is
// zero with from_platform false; after a reading, grabs go on at the last known pose. Each
// loss of the daemon is logged once (with where it was and the pose kept), and its return once.
#pragma once

#include <boost/asio/io_context.hpp>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "common/base/result.h"
#include "common/config/process_options.h"
#include "common/geometry/platform.h"
#include "common/net/client.h"
#include "igms/devices.pb.h"
#include "video_server/stereo_frame.h"

namespace igms::video {

// The pose a PlatformState stands for (see above for the two conversions).
PoseStamp PoseFromPlatformState(const devices::PlatformState& state,
                                const std::optional<geometry::PlatformModel>& model);

struct PlatformFollowOptions {
  std::string process;  // the platform's name in the lab, for logs
  net::ClientOptions client;
  std::optional<geometry::PlatformModel> model;  // tick scales; none = the daemon's degrees
};

// The follow options the lab configuration gives process `process` (its `platform` key,
// declared by VideoKeys): nullopt when its section names no platform (the pose stays zero);
// an error naming the key when it is misconfigured.
Result<std::optional<PlatformFollowOptions>> ConfiguredPlatformFollow(
    const config::ProcessOptions& process);

class PlatformPoseFollower {
 public:
  // Runs its client on `io` (the server's io_context). Start() subscribes.
  PlatformPoseFollower(boost::asio::io_context& io, PlatformFollowOptions options);
  ~PlatformPoseFollower();
  PlatformPoseFollower(const PlatformPoseFollower&) = delete;
  PlatformPoseFollower& operator=(const PlatformPoseFollower&) = delete;

  void Start();
  void Stop();

  // The latest pose (thread-safe, never blocks on the network).
  PoseStamp Pose() const;
  // Readings received since Start().
  uint64_t readings() const;

 private:
  void OnReading(const devices::PlatformState& state);
  void OnConnection(net::ConnectionState state, const std::string& reason);

  PlatformFollowOptions options_;
  net::Client client_;
  mutable std::mutex mutex_;
  PoseStamp pose_;
  uint64_t readings_ = 0;
  bool reported_loss_ = false;
  bool ever_connected_ = false;
};

}  // namespace igms::video
