// The video server follows the camera platform: real igms-platformd (simulated MOLLY) and
// igms-video-server (sim backend) processes on loopback, wired by a small lab configuration.
// A commanded pan and tilt must stamp the grab with the pose the platform reports reaching,
// and move the rendered image exactly as the calibration's platform model predicts.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/base/clock.h"
#include "common/calibration/calibration_file.h"
#include "common/geometry/platform.h"
#include "common/sim/capture/sim_capture.h"
#include "common/sim/renderer.h"
#include "common/sim/scene_yaml.h"
#include "common/sim/testbed.h"
#include "common/wire/image_message.h"
#include "igms/devices.pb.h"
#include "igms/video.pb.h"
#include "tests/support/video_server_process.h"
#include "tests/support/wait_for.h"
#include "tests/video_server/test_data.h"

namespace igms::video {
namespace {

using wire::DecodeProtoImage;

using namespace std::chrono_literals;
using testing::ScratchDir;
using testing::ServerProcess;
using testing::TestClient;
const std::string kVideo = "igms.video.VideoService.";
const std::string kPlatform = "igms.devices.PlatformService.";

std::string CalibrationPath() { return igms::testing::ThesisCalibration(); }

using igms::testing::WaitFor;

// igms-platformd --simulate on an ephemeral port.
class PlatformDaemon : public igms::testing::ChildProcess {
 public:
  PlatformDaemon() : ChildProcess("igms-platformd", {"--simulate", "--port", "0"}) {}
  ~PlatformDaemon() { Terminate(); }
  uint16_t WaitPort() { return WaitListening(); }
};

// The newest reading of the platform's Live stream, seen from the test.
class PlatformWatch {
 public:
  explicit PlatformWatch(TestClient& client) {
    client->Subscribe<devices::PlatformState>(kPlatform + "Live", devices::SubscribeRequest(),
                                              [this](const devices::PlatformState& s) {
                                                std::lock_guard lock(mutex_);
                                                last_ = s;
                                                ++count_;
                                              });
  }
  devices::PlatformState last() {
    std::lock_guard lock(mutex_);
    return last_;
  }
  int count() {
    std::lock_guard lock(mutex_);
    return count_;
  }

 private:
  std::mutex mutex_;
  devices::PlatformState last_;
  int count_ = 0;
};

// One white sphere on the table, in front of the cameras, rendered without noise or blur so
// the blob's centroid is the silhouette's.
site::Scene OneSphereScene() {
  site::Scene scene = site::DefaultTestbedScene();
  scene.objects.clear();
  site::SceneObject ball;
  ball.name = "ball";
  ball.shape = site::Sphere{Eigen::Vector3d(16.0, -40.0, 1.5), 1.5};
  scene.objects.push_back(ball);
  scene.sensor.noise_sigma = 0.0;
  scene.sensor.blur_sigma = 0.0;
  return scene;
}

// The lab: the platform daemon at `platform_port`, the video server's section naming it.
// `backend`: the video section's backend lines (the one-sphere site by default).
std::string WriteLab(const ScratchDir& scratch, uint16_t platform_port, std::string backend = "") {
  if (backend.empty()) {
    const std::string scene = scratch.File("scene.yaml");
    std::ofstream(scene) << site::SceneToYaml(OneSphereScene());
    backend = "    backend: sim\n    sim: {scene: " + scene + "}\n";
  }
  std::string path = scratch.File("lab.yaml");
  std::ofstream(path) << "lab:\n  calibration: " << CalibrationPath()
                      << "\nprocesses:\n  video:\n    program: igms-video-server\n"
                      << backend << "    platform: platform\n"
                      << "  platform:\n    program: igms-platformd\n    host: 127.0.0.1\n"
                      << "    port: " << platform_port << "\n    serial: simulate\n";
  return path;
}

struct Grabbed {
  PlatformPose pose;
  cv::Mat left, right;
};

Grabbed Grab(TestClient& video) {
  Grabbed out;
  auto grab = video->CallSync<GrabResponse>(kVideo + "Grab", GrabRequest{}, 20s);
  EXPECT_TRUE(grab.ok()) << grab.status.message;
  if (!grab.ok()) return out;
  out.pose = grab.value.pose();
  GetImagesRequest request;
  request.set_frame_id(grab.value.frame_id());
  request.set_encoding(PNG);
  auto images = video->CallSync<GetImagesResponse>(kVideo + "GetImages", request, 20s);
  EXPECT_TRUE(images.ok()) << images.status.message;
  if (!images.ok()) return out;
  out.left = DecodeProtoImage(images.value.left());
  out.right = DecodeProtoImage(images.value.right());
  return out;
}

// Centroid of the sphere's silhouette: the pixels brighter than halfway between the dark
// table (about 30 grey levels) and the sphere's darkest lit part (above 120). A binary mask,
// so the shading (brighter on top) does not pull the centroid towards the light.
std::optional<Eigen::Vector2d> BlobCentroid(const cv::Mat& image) {
  cv::Mat mask;
  cv::threshold(image, mask, 75, 1, cv::THRESH_BINARY);
  const cv::Moments m = cv::moments(mask, true);
  if (m.m00 < 100.0) return std::nullopt;
  return Eigen::Vector2d(m.m10 / m.m00, m.m01 / m.m00);
}

std::vector<double> Joints(const PlatformPose& pose) {
  return {pose.joints_rad().begin(), pose.joints_rad().end()};
}

TEST(PlatformPose, GrabsFollowThePlatformAndTheImageMovesAsTheModelSays) {
  ScratchDir scratch;
  PlatformDaemon platformd;
  const uint16_t platform_port = platformd.WaitPort();
  ASSERT_NE(platform_port, 0) << platformd.Log();
  ServerProcess server({"--config", WriteLab(scratch, platform_port)});
  const uint16_t port = server.WaitPort();
  ASSERT_NE(port, 0) << server.Log();
  const auto calibration = calibration::LoadCalibration(CalibrationPath());
  ASSERT_TRUE(calibration.ok() && calibration->platform);
  const geometry::PlatformModel& model = *calibration->platform;

  TestClient platform(platform_port);
  PlatformWatch watch(platform);
  TestClient video(port);
  ASSERT_TRUE(WaitFor("three platform readings", [&] { return watch.count() > 2; }));

  // At the zero pose, once the server has heard the platform.
  Grabbed zero;
  ASSERT_TRUE(WaitFor("a grab stamped with the platform pose", [&] {
    zero = Grab(video);
    return zero.pose.from_platform();
  })) << server.Log();
  ASSERT_EQ(zero.pose.joints_rad_size(), 3);
  EXPECT_EQ(Joints(zero.pose), std::vector<double>(3, 0.0));

  // Pan 2 degrees left and tilt 1 degree up, then wait for the platform to get there.
  devices::SetOrientationRequest set;
  set.set_yaw_ticks(543);
  set.set_pitch_ticks(57);
  auto moved =
      platform->CallSync<devices::SetOrientationResponse>(kPlatform + "SetOrientation", set, 5s);
  ASSERT_TRUE(moved.ok()) << moved.status.message;
  ASSERT_TRUE(WaitFor("the platform at rest at the pan", [&] {
    const auto s = watch.last();
    return !s.moving() && s.yaw_ticks() == 543 && s.pitch_ticks() == 57;
  })) << watch.last().DebugString();
  const devices::PlatformState reached = watch.last();
  const int64_t before_grab = UnixNs();
  Grabbed panned;
  ASSERT_TRUE(WaitFor("a grab at the panned pose", [&] {
    panned = Grab(video);
    return panned.pose.joints_rad_size() == 3 && panned.pose.joints_rad(0) != 0.0;
  }));

  // The stamp: what the platform reports reaching, in the model's tick scales.
  EXPECT_TRUE(panned.pose.from_platform());
  const std::vector<double> q = Joints(panned.pose);
  EXPECT_EQ(q[0], reached.yaw_ticks() * model.joints[0].radians_per_tick);
  EXPECT_EQ(q[1], reached.pitch_ticks() * model.joints[1].radians_per_tick);
  EXPECT_EQ(q[2], 0.0);
  EXPECT_NEAR(q[0], reached.yaw_deg() * M_PI / 180, 1e-12);
  EXPECT_NEAR(q[1], reached.pitch_deg() * M_PI / 180, 1e-12);
  EXPECT_GT(panned.pose.time_unix_ns(), 0);
  EXPECT_LE(panned.pose.time_unix_ns(), UnixNs());
  EXPECT_GT(panned.pose.time_unix_ns(), before_grab - 2'000'000'000LL);

  // The image: the sphere's blob sits where CameraAtPose projects its centre, in both
  // cameras, and it moved (right, as the view panned left; down, as it tilted up).
  const Eigen::Vector3d centre(16.0, -40.0, 1.5);
  for (int side = 0; side < 2; ++side) {
    const auto& cal = side == 0 ? calibration->left : calibration->right;
    const cv::Mat& before = side == 0 ? zero.left : zero.right;
    const cv::Mat& after = side == 0 ? panned.left : panned.right;
    const auto blob0 = BlobCentroid(before);
    const auto blob1 = BlobCentroid(after);
    ASSERT_TRUE(blob0 && blob1);
    const geometry::ProjectiveCamera at_zero(cal.P, cal.image_size);
    const geometry::ProjectiveCamera at_pose(geometry::CameraAtPose(cal.P, model, q),
                                             cal.image_size);
    const Eigen::Vector2d predicted0 = *at_zero.Project(centre);
    const Eigen::Vector2d predicted1 = *at_pose.Project(centre);
    EXPECT_LT((*blob0 - predicted0).norm(), 0.5) << "side " << side;
    EXPECT_LT((*blob1 - predicted1).norm(), 0.5) << "side " << side;
    EXPECT_GT(blob1->x() - blob0->x(), 20.0) << "side " << side;
    EXPECT_GT(blob1->y() - blob0->y(), 5.0) << "side " << side;
  }

  // And the pair is exactly the simulated site rendered at that pose.
  site::Scene scene = OneSphereScene();
  scene.cameras = {calibration->left.Camera(), calibration->right.Camera()};
  PoseStamp pose;
  pose.joints_rad = {q[0], q[1], q[2]};
  scene.cameras = CamerasAtPose(scene.cameras, calibration->platform, pose);
  const site::StereoImages expected = site::RenderStereo(scene);
  EXPECT_EQ(cv::norm(expected.left, panned.left, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(expected.right, panned.right, cv::NORM_INF), 0.0);

  // Live video goes through the same backend: its frames carry the pose and show the view
  // at it.
  std::mutex live_mutex;
  std::optional<LiveFrame> live;
  LiveRequest live_request;
  live_request.set_fps(10);
  live_request.set_encoding(PNG);
  video->Subscribe<LiveFrame>(kVideo + "Live", live_request, [&](const LiveFrame& frame) {
    std::lock_guard lock(live_mutex);
    live = frame;
  });
  ASSERT_TRUE(WaitFor("the live frame", [&] {
    std::lock_guard lock(live_mutex);
    return live.has_value();
  }));
  std::lock_guard lock(live_mutex);
  EXPECT_TRUE(live->pose().from_platform());
  EXPECT_EQ(Joints(live->pose()), q);
  EXPECT_EQ(cv::norm(expected.left, DecodeProtoImage(live->left()), cv::NORM_INF), 0.0);
  EXPECT_EQ(server.Stop(), 0);
}

TEST(PlatformPose, GrabsGoOnAtTheLastPoseWhenThePlatformDies) {
  ScratchDir scratch;
  PlatformDaemon platformd;
  const uint16_t platform_port = platformd.WaitPort();
  ASSERT_NE(platform_port, 0) << platformd.Log();
  ServerProcess server({"--config", WriteLab(scratch, platform_port)});
  const uint16_t port = server.WaitPort();
  ASSERT_NE(port, 0) << server.Log();
  {
    TestClient platform(platform_port);
    PlatformWatch watch(platform);
    devices::SetOrientationRequest set;
    set.set_yaw_ticks(-800);
    ASSERT_TRUE(WaitFor("a platform reading", [&] { return watch.count() > 0; }));
    ASSERT_TRUE(
        platform->CallSync<devices::SetOrientationResponse>(kPlatform + "SetOrientation", set, 5s)
            .ok());
    ASSERT_TRUE(WaitFor("the platform at rest at yaw -800", [&] {
      return !watch.last().moving() && watch.last().yaw_ticks() == -800;
    }));
  }
  TestClient video(port);
  Grabbed before;
  ASSERT_TRUE(WaitFor("a grab at the negative yaw", [&] {
    before = Grab(video);
    return before.pose.joints_rad_size() == 3 && before.pose.joints_rad(0) < 0.0;
  }));

  platformd.Kill();
  for (int i = 0; i < 3; ++i) {
    const auto start = std::chrono::steady_clock::now();
    Grabbed after = Grab(video);
    EXPECT_LT(std::chrono::steady_clock::now() - start, 5s);
    EXPECT_TRUE(after.pose.from_platform());
    EXPECT_EQ(Joints(after.pose), Joints(before.pose));
    EXPECT_EQ(cv::norm(after.left, before.left, cv::NORM_INF), 0.0);
    std::this_thread::sleep_for(300ms);  // across a few reconnection attempts
  }
  ASSERT_TRUE(WaitFor("the server to log the lost platform daemon", [&] {
    return server.Log().find("lost the platform daemon") != std::string::npos;
  }));
  const std::string text = server.Log();
  size_t losses = 0;
  for (size_t at = text.find("lost the platform"); at != std::string::npos;
       at = text.find("lost the platform", at + 1)) {
    ++losses;
  }
  EXPECT_EQ(losses, 1u) << text;
  EXPECT_EQ(server.Stop(), 0);
}

TEST(PlatformPose, FilesBackendPassesThePoseThrough) {
  IGMS_REQUIRE_OPENCV_DATA();
  ScratchDir scratch;
  PlatformDaemon platformd;
  const uint16_t platform_port = platformd.WaitPort();
  ASSERT_NE(platform_port, 0) << platformd.Log();
  const std::string backend =
      "    backend: files\n    files: {left: " + testing::OpenCvData("left01.jpg") +
      ", right: " + testing::OpenCvData("right01.jpg") + "}\n";
  ServerProcess server({"--config", WriteLab(scratch, platform_port, backend)});
  const uint16_t port = server.WaitPort();
  ASSERT_NE(port, 0) << server.Log();
  TestClient platform(platform_port);
  PlatformWatch watch(platform);
  devices::SetOrientationRequest set;
  set.set_yaw_ticks(-2714);  // 10 degrees right
  set.set_roll_ticks(30);
  ASSERT_TRUE(WaitFor("a platform reading", [&] { return watch.count() > 0; }));
  ASSERT_TRUE(
      platform->CallSync<devices::SetOrientationResponse>(kPlatform + "SetOrientation", set, 5s)
          .ok());
  ASSERT_TRUE(WaitFor("the platform at rest at yaw -2714 roll 30", [&] {
    const auto s = watch.last();
    return !s.moving() && s.yaw_ticks() == -2714 && s.roll_ticks() == 30;
  }));
  const auto calibration = calibration::LoadCalibration(CalibrationPath());
  ASSERT_TRUE(calibration.ok() && calibration->platform);
  TestClient video(port);
  Grabbed grabbed;
  ASSERT_TRUE(WaitFor("a grab at that pose", [&] {
    grabbed = Grab(video);
    return grabbed.pose.joints_rad_size() == 3 && grabbed.pose.joints_rad(0) < 0.0 &&
           grabbed.pose.joints_rad(2) != 0.0;
  }));
  EXPECT_TRUE(grabbed.pose.from_platform());
  EXPECT_EQ(grabbed.pose.joints_rad(0), -2714 * calibration->platform->joints[0].radians_per_tick);
  EXPECT_EQ(grabbed.pose.joints_rad(1), 0.0);
  EXPECT_EQ(grabbed.pose.joints_rad(2), 30 * calibration->platform->joints[2].radians_per_tick);
  // The images are the files, untouched by the pose.
  const cv::Mat left = cv::imread(testing::OpenCvData("left01.jpg"), cv::IMREAD_GRAYSCALE);
  EXPECT_EQ(cv::norm(left, grabbed.left, cv::NORM_INF), 0.0);
  EXPECT_EQ(server.Stop(), 0);
}

TEST(PlatformPose, NoPlatformDaemonListeningGrabsAtTheZeroPose) {
  ScratchDir scratch;
  // A port nothing listens on: the platform's port is taken from a daemon already gone.
  uint16_t dead_port = 0;
  {
    PlatformDaemon gone;
    dead_port = gone.WaitPort();
    ASSERT_NE(dead_port, 0) << gone.Log();
  }
  ServerProcess server({"--config", WriteLab(scratch, dead_port)});
  const uint16_t port = server.WaitPort();
  ASSERT_NE(port, 0) << server.Log();
  TestClient video(port);
  const auto start = std::chrono::steady_clock::now();
  Grabbed grabbed = Grab(video);
  EXPECT_LT(std::chrono::steady_clock::now() - start, 5s);
  EXPECT_FALSE(grabbed.pose.from_platform());
  EXPECT_EQ(Joints(grabbed.pose), std::vector<double>(3, 0.0));
  ASSERT_FALSE(grabbed.left.empty());
  EXPECT_EQ(server.Stop(), 0);
}

TEST(PlatformPose, NamingAProcessTheLabDoesNotHaveIsAConfigurationError) {
  ServerProcess server(
      {"--set", "processes.video.backend=sim", "--set", "processes.video.platform=nowhere"});
  EXPECT_EQ(server.Wait(20s), 2);
  EXPECT_NE(server.Log().find("processes.video.platform"), std::string::npos) << server.Log();
}

}  // namespace
}  // namespace igms::video
