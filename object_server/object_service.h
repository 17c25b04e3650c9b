// The object server's service: igms.object.ObjectService.Locate over the net library
// (docs/protocol-object.md). A request is validated on the io thread, then queued for a
// pool of worker threads; a worker fetches the frame's images from the video server (kept
// in a small cache: an operator models several objects on one grab), runs the locator and
// replies. Several requests are located at once, one per worker.
//
// Errors (envelope ERROR): BAD_REQUEST for a request that is not four finite marks and a
// known type; NOT_FOUND for a frame the video server does not hold; UNAVAILABLE when the
// video server does not answer within fetch_timeout, or at once when its connection is
// refused or lost, naming the video server and why (the video client reconnects by itself,
// so a later request succeeds once the video server is back). A locate that runs and finds
// nothing is a normal response with found = false and a reason.
//
// igms.object.ObjectService.Status answers the calibration's file and hash and the video
// server's address and connection, so a client can check it shares both.
#pragma once

#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "common/calibration/calibration_file.h"
#include "common/config/keys.h"
#include "common/geometry/camera.h"
#include "common/geometry/platform.h"
#include "common/net/client.h"
#include "common/net/server.h"
#include "igms/object.pb.h"
#include "object_server/locate.h"
#include "object_server/ranger.h"

namespace igms::object {

struct ObjectServiceOptions {
  // One GetImages call to the video server; shorter than the callers' own timeouts
  // (igmsctl's 5 s), so that a video server that hangs is reported as such, not as the
  // caller's timeout.
  std::chrono::milliseconds fetch_timeout{2000};
  size_t cache_frames = 4;  // grabs' images kept
  size_t max_queue = 16;    // locates waiting; more are UNAVAILABLE
  int workers = 2;          // locates run at once
  LocateOptions locate;
  // The ultrasonic ranger in the world (the calibration's ranger map at the platform's zero
  // pose, as the cameras); without one a request's range is not used (said in the response).
  std::optional<RangerPose> ranger;
  // The camera platform (the calibration's `platform` and `ranger` maps). A frame the video
  // server grabbed at a non-zero platform pose is located with both cameras at
  // CameraAtPose(P0, platform, q) and the ranger moved by the same pose, since the marks are
  // world points. Without a model such a frame is located at the zero pose, with a warning.
  std::optional<geometry::PlatformModel> platform;
  std::optional<calibration::RangerCalibration> ranger_mount;
  // For Status and messages: the calibration's file and its CalibrationHash
  // (common/calibration/calibration_hash.h), and the video server's host:port.
  std::string calibration_file;
  std::string calibration_sha256;
  std::string video = "the video server";
  std::string video_process = "video";  // the lab's process it fetches frames from
  // False, with what is wrong in *error, when invalid.
  bool Check(std::string* error) const;
};

// The object server's keys (processes.NAME): fetch_timeout_ms, cache_frames, workers,
// camera_blur_px and video (bound to `options`), max_frame_bytes (net::ServerKeys); and
// lab.calibration, which it requires.
config::Keys ObjectKeys(ObjectServiceOptions* options);

// BAD_REQUEST with a message naming what is wrong, or Ok.
net::Status ValidateLocateRequest(const igms::object::LocateRequest& request);

// `camera` (calibrated at the platform's zero pose) moved with the platform to `joints_rad`.
geometry::ProjectiveCamera CameraAtPose(const geometry::ProjectiveCamera& camera,
                                        const geometry::PlatformModel& platform,
                                        std::span<const double> joints_rad);

// The response form of a locator result.
void ResultToProto(const LocateResult& result, igms::object::LocateResponse* response);
// A request's known solid as the locator's, or nullopt with why not (an unknown type, a
// number that is not finite, a size that is not positive).
std::optional<KnownShape> KnownFromProto(const igms::object::KnownSolid& known, std::string* why);
// A client's side: the operator's four marks (world units) into a request, after any there.
void MarksToProto(const std::array<Eigen::Vector3d, 4>& marks,
                  igms::object::LocateRequest* request);

class ObjectService {
 public:
  // `video` must outlive the service; its calls are made from the workers. The service sets
  // its OnStateChange, to know at once when the video server is down.
  ObjectService(net::Client& video, geometry::ProjectiveCamera left,
                geometry::ProjectiveCamera right, ObjectServiceOptions options);
  ~ObjectService();  // finishes the locate running, answers the queued ones SHUTTING_DOWN
  ObjectService(const ObjectService&) = delete;
  ObjectService& operator=(const ObjectService&) = delete;

  void Register(net::Server& server);

 private:
  struct Frame {
    uint64_t id = 0;
    cv::Mat left, right;
    std::vector<double> joints_rad;  // the platform pose at the grab (empty or zeros: none)
  };
  using Job = std::function<void(bool run)>;  // run false: shutting down
  void Work();
  void Run(const igms::object::LocateRequest& request,
           net::Reply<igms::object::LocateResponse> reply);
  // The frame's images from the cache or the video server; status NOT_FOUND / UNAVAILABLE.
  net::Status Fetch(uint64_t frame_id, Frame* frame, double* fetch_ms);
  // True when the video client is connected, waiting (within fetch_timeout) for a
  // connection being made; false with why when it is down.
  bool VideoUp(std::string* why);

  // The video client's connection as it last changed, shared with its state callback.
  struct VideoLink {
    std::mutex mutex;
    std::condition_variable changed;
    net::ConnectionState state = net::ConnectionState::kConnecting;
    std::string reason;
  };

  net::Client& video_;
  std::shared_ptr<VideoLink> link_ = std::make_shared<VideoLink>();
  geometry::ProjectiveCamera left_camera_, right_camera_;
  ObjectServiceOptions options_;
  std::mutex cache_mutex_;
  std::list<Frame> cache_;  // most recent first; under cache_mutex_

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Job> queue_;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace igms::object
