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
  BackendChoice choice = MakeConfiguredBackend(VideoWithBackend("sim"));
  EXPECT_FALSE(choice.backend);
  EXPECT_EQ(choice.error, "processes.video.backend: unknown backend 'sim' (files or camera)");
  EXPECT_EQ(CaptureBackendNames(), (std::vector<std::string>{"files", "camera"}));

  RegisterSimCapture();
  EXPECT_EQ(CaptureBackendNames(), (std::vector<std::string>{"files", "camera", "sim"}));
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

}  // namespace
}  // namespace igms::video
