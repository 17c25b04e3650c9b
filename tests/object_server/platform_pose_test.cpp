// The object server locates a frame grabbed with the camera platform turned: the platform
// daemon, the video server following it and the object server run as real processes on
// loopback; the marks are world points placed for the turned cameras, and the object must
// come out where it is in the world, which it cannot unless the server moves its cameras
// to the frame's pose.
#include <gtest/gtest.h>

#include <fstream>

#include "common/calibration/calibration_file.h"
#include "common/sim/marks.h"
#include "common/sim/testbed.h"
#include "igms/devices.pb.h"
#include "igms/object.pb.h"
#include "igms/video.pb.h"
#include "object_server/object_service.h"
#include "tests/support/child_process.h"

namespace igms::object {
namespace {

using namespace std::chrono_literals;
using igms::testing::ChildProcess;
using igms::testing::ScratchDir;
using igms::testing::TestClient;

TEST(ObjectServerPlatformPose, LocatesAFrameGrabbedWithThePlatformTurned) {
  ScratchDir scratch;
  ChildProcess platformd("igms-platformd", {"--simulate", "--port", "0"});
  const uint16_t platform_port = platformd.WaitListening();
  ASSERT_NE(platform_port, 0) << platformd.Log();
  const std::string lab = scratch.File("lab.yaml");
  std::ofstream(lab) << "lab:\n  calibration: " << igms::testing::ThesisCalibration()
                     << "\nprocesses:\n"
                     << "  video:\n    program: igms-video-server\n    port: 0\n"
                     << "    backend: sim\n    platform: platform\n"
                     << "  object:\n    program: igms-object-server\n    port: 0\n"
                     << "    video: video\n"
                     << "  platform:\n    program: igms-platformd\n    host: 127.0.0.1\n"
                     << "    port: " << platform_port << "\n    serial: simulate\n";
  ChildProcess video("igms-video-server", {"--config", lab, "--name", "video"});
  const uint16_t video_port = video.WaitListening();
  ASSERT_NE(video_port, 0) << video.Log();
  ChildProcess object("igms-object-server", {"--config", lab, "--name", "object", "--set",
                                             "processes.video.port=" + std::to_string(video_port)});
  const uint16_t object_port = object.WaitListening();
  ASSERT_NE(object_port, 0) << object.Log();

  // Pan 1.5 degrees: the testbed's objects stay in view, and move about 8 px in the image,
  // so marks and triangulation at the zero pose would put them more than an inch away.
  TestClient platform(platform_port);
  devices::SetOrientationRequest set;
  set.set_yaw_ticks(407);
  auto moved = platform->CallSync<devices::SetOrientationResponse>(
      "igms.devices.PlatformService.SetOrientation", set, 5s);
  ASSERT_TRUE(moved.ok()) << moved.status.message;
  TestClient videoc(video_port);
  video::GrabResponse grab;
  double last_yaw = 0.0;
  ASSERT_TRUE(igms::testing::WaitUntil([&] {
    auto g = videoc->CallSync<video::GrabResponse>("igms.video.VideoService.Grab",
                                                   video::GrabRequest{}, 20s);
    if (!g.ok()) return false;
    grab = g.value;
    // Settled: two grabs in a row at the same non-zero yaw.
    const double yaw = grab.pose().joints_rad_size() == 3 ? grab.pose().joints_rad(0) : 0.0;
    const bool settled = yaw != 0.0 && yaw == last_yaw;
    last_yaw = yaw;
    return settled;
  })) << video.Log();

  const auto calibration = calibration::LoadCalibration(igms::testing::ThesisCalibration());
  ASSERT_TRUE(calibration.ok() && calibration->platform);
  const std::vector<double> q(grab.pose().joints_rad().begin(), grab.pose().joints_rad().end());
  const geometry::ProjectiveCamera left =
      CameraAtPose(calibration->left.Camera(), *calibration->platform, q);

  const site::Scene scene = site::DefaultTestbedScene();
  TestClient client(object_port);
  int located = 0;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const auto* cyl = std::get_if<site::Cylinder>(&scene.objects[i].shape);
    if (!cyl || std::abs(cyl->axis.z()) < 0.9) continue;  // the upright cylinders
    const auto marks = site::GenerateMarks(scene.objects[i].shape, left, 100 + i);
    ASSERT_TRUE(marks) << scene.objects[i].name;
    LocateRequest request;
    request.set_type(OBJECT_TYPE_CYLINDER);
    request.set_frame_id(grab.frame_id());
    MarksToProto(*marks, &request);
    auto got = client->CallSync<LocateResponse>("igms.object.ObjectService.Locate", request, 60s);
    ASSERT_TRUE(got.ok()) << got.status.message;
    ASSERT_TRUE(got.value.found()) << scene.objects[i].name << ": " << got.value.detail();
    const auto& c = got.value.cylinder().center();
    EXPECT_LT((Eigen::Vector3d(c.x(), c.y(), c.z()) - cyl->center).norm(), 0.3)
        << scene.objects[i].name;
    EXPECT_NEAR(got.value.cylinder().radius(), cyl->radius, 0.05) << scene.objects[i].name;
    ++located;
  }
  EXPECT_GE(located, 2);
}

}  // namespace
}  // namespace igms::object
