// The sim backend in the real igms-video-server process: a grabbed pair is the simulated
// site rendered directly with the same scene, cameras and seed.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/core.hpp>

#include "common/calibration/calibration_file.h"
#include "common/sim/renderer.h"
#include "common/sim/scene_yaml.h"
#include "common/sim/testbed.h"
#include "common/wire/image_message.h"
#include "igms/video.pb.h"
#include "tests/support/video_server_process.h"

namespace igms::video {
namespace {

using wire::DecodeProtoImage;

using namespace std::chrono_literals;
using testing::ScratchDir;
using testing::ServerProcess;
using testing::TestClient;
const std::string kService = "igms.video.VideoService.";

// Grabs one pair and fetches both images losslessly.
GetImagesResponse GrabPair(uint16_t port) {
  TestClient client(port);
  auto grab = client->CallSync<GrabResponse>(kService + "Grab", GrabRequest{}, 60s);
  EXPECT_TRUE(grab.ok()) << grab.status.message;
  GetImagesRequest request;
  request.set_frame_id(grab.value.frame_id());
  request.set_encoding(PNG);
  auto images = client->CallSync<GetImagesResponse>(kService + "GetImages", request, 20s);
  EXPECT_TRUE(images.ok()) << images.status.message;
  return images.value;
}

void ExpectSame(const cv::Mat& expected, const Image& got) {
  cv::Mat image = DecodeProtoImage(got);
  ASSERT_EQ(image.size(), expected.size());
  ASSERT_EQ(image.type(), expected.type());
  EXPECT_EQ(cv::norm(image, expected, cv::NORM_INF), 0.0);
}

TEST(SimBackend, DefaultTestbedThroughTheLabCalibration) {
  ScratchDir scratch;
  const std::string calibration = igms::testing::ThesisCalibration();
  ServerProcess server({"--set", "processes.video.backend=sim", "--set",
                        "lab.calibration=" + calibration, "--set", "processes.video.sim.seed=7"});
  const uint16_t port = server.WaitPort();
  ASSERT_NE(port, 0) << "the server did not start";
  GetImagesResponse got = GrabPair(port);

  site::Scene scene = site::DefaultTestbedScene();
  auto cal = calibration::LoadCalibration(calibration);
  ASSERT_TRUE(cal.ok()) << cal.error();
  scene.cameras.left = cal->left.Camera();
  scene.cameras.right = cal->right.Camera();
  scene.sensor.seed = 7;
  site::StereoImages expected = site::RenderStereo(scene);
  ExpectSame(expected.left, got.left());
  ExpectSame(expected.right, got.right());
  // The noise differs between sides and from another seed: the comparison can fail.
  scene.sensor.seed = 8;
  EXPECT_GT(cv::norm(site::RenderStereo(scene).left, expected.left, cv::NORM_INF), 0.0);
}

TEST(SimBackend, SceneFileNamedInTheVideoSection) {
  ScratchDir scratch;
  site::Scene scene = site::RandomTestbedScene(5);
  scene.sensor.seed = 3;
  const std::string path = scratch.File("scene.yaml");
  std::ofstream(path) << site::SceneToYaml(scene);
  ServerProcess server(
      {"--set", "processes.video.backend=sim", "--set", "processes.video.sim.scene=" + path});
  const uint16_t port = server.WaitPort();
  ASSERT_NE(port, 0) << "the server did not start";
  GetImagesResponse got = GrabPair(port);
  site::Scene reread = *site::LoadSceneFile(path).scene;
  site::StereoImages expected = site::RenderStereo(reread);
  ExpectSame(expected.left, got.left());
  ExpectSame(expected.right, got.right());
}

TEST(SimBackend, MissingSceneFileIsAConfigurationError) {
  ScratchDir scratch;
  ServerProcess server({"--set", "processes.video.backend=sim", "--set",
                        "processes.video.sim.scene=" + scratch.File("none.yaml")});
  EXPECT_EQ(server.Wait(20s), 2);
}

}  // namespace
}  // namespace igms::video
