// Capture backends chosen at run time: the video server's library knows files and camera;
// `sim` exists only once a program links the simulation and registers it, and an unknown
// name is refused with the names that would work.
#include "video_server/capture_registry.h"

#include <gtest/gtest.h>

#include "common/config/lab_config.h"
#include "common/sim/capture/sim_capture.h"
#include "video_server/video_config.h"

namespace igms::video {
namespace {

config::ProcessOptions VideoWithBackend(const std::string& backend) {
  config::ProcessOptions process;
  process.name = "video";
  process.config =
      config::LabConfig::FromString("processes:\n  video:\n    backend: " + backend + "\n");
  return process;
}

TEST(CaptureRegistry, SimExistsOnceRegisteredAndUnknownNamesListTheRest) {
  // The library alone: no simulation linked in, so `sim` is an unknown backend.
  VideoConfig unused;
  EXPECT_EQ(VideoKeys(&unused).Find("sim.scene"), nullptr);
  BackendChoice choice = MakeConfiguredBackend(VideoWithBackend("sim"));
  EXPECT_FALSE(choice.backend);
  EXPECT_EQ(choice.error, "processes.video.backend: unknown backend 'sim' (files or camera)");
  EXPECT_EQ(CaptureBackendNames(), (std::vector<std::string>{"files", "camera"}));

  RegisterSimCapture();
  EXPECT_EQ(CaptureBackendNames(), (std::vector<std::string>{"files", "camera", "sim"}));
  // Its keys are the video server's once registered: checked and listed like the others.
  const config::Keys keys = VideoKeys(&unused);
  ASSERT_NE(keys.Find("sim.scene"), nullptr);
  EXPECT_EQ(keys.Find("sim.scene")->type, config::KeyType::kPath);
  ASSERT_NE(keys.Find("sim.seed"), nullptr);
  choice = MakeConfiguredBackend(VideoWithBackend("sim"));
  ASSERT_TRUE(choice.backend) << choice.error;
  EXPECT_EQ(choice.backend->Describe().rfind("sim: default testbed", 0), 0u)
      << choice.backend->Describe();
  const CaptureResult grab = choice.backend->Capture(PoseStamp{});
  ASSERT_TRUE(grab.ok()) << grab.error;
  EXPECT_EQ(grab.images->left.cols, 512);

  choice = MakeConfiguredBackend(VideoWithBackend("simulated"));
  EXPECT_FALSE(choice.backend);
  EXPECT_EQ(choice.error,
            "processes.video.backend: unknown backend 'simulated' (files, camera or sim)");
}

// The video keys fill VideoConfig: paths beside the lab file, device indices as given.
TEST(VideoConfig, KeysFillTheOptions) {
  config::ProcessOptions process;
  process.name = "video";
  process.config = config::LabConfig::FromString(
      "processes:\n  video:\n    backend: camera\n    camera: {left: '2', right: cams/r.avi, "
      "frame_timeout_ms: 250}\n    edges: {sigma: 2.5}\n    store_capacity: 3\n");
  const VideoConfig c = ReadVideoConfig(process);
  EXPECT_EQ(c.backend, "camera");
  EXPECT_EQ(c.camera.left, "2");
  EXPECT_EQ(c.camera.right, process.config.ResolvePath("cams/r.avi"));
  EXPECT_EQ(c.camera.frame_timeout, std::chrono::milliseconds(250));
  EXPECT_EQ(c.camera.retry_interval, std::chrono::milliseconds(1000));
  EXPECT_DOUBLE_EQ(c.service.edges.sigma, 2.5);
  EXPECT_EQ(c.service.store_capacity, 3u);
  EXPECT_EQ(c.encoding, "png");
  process.config.Set("processes.video.edges.sigma", "wide");
  EXPECT_THROW(ReadVideoConfig(process), config::ConfigError);
}

}  // namespace
}  // namespace igms::video
