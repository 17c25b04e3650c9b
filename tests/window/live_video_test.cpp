// The window's live video against a real video server (files backend, the opencv-doc stereo
// pair: 1282 x 1110 colour, raw pairs of 8.5 MB, over the net client's default frame
// limit): frames arrive whole, the overlay offset is stored on the server, and a server that
// goes away is reported lost while the last frame stays; the server's clock offset is
// estimated from pings at connection and the latency is taken on it.
#include "control/window/live_video.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/support/video_server_process.h"
#include "tests/support/wait_for.h"
#include "tests/video_server/test_data.h"

namespace igms::control {
namespace {

using video::testing::OpenCvData;

TEST(LiveVideo, FramesOverTheDefaultLimitArriveAndALostServerIsReported) {
  IGMS_REQUIRE_OPENCV_DATA();
  video::testing::ScratchDir scratch;
  auto server = std::make_unique<video::testing::ServerProcess>(
      std::vector<std::string>{"--set", "processes.video.files.left=" + OpenCvData("aloeL.jpg"),
                               "--set", "processes.video.files.right=" + OpenCvData("aloeR.jpg"),
                               "--set", "processes.video.files.colour=true", "--set",
                               "processes.video.overlay_file=" + scratch.File("overlay.yaml")});
  const uint16_t port = server->WaitPort();
  ASSERT_NE(port, 0);
  ASSERT_GT(size_t{1282} * 1110 * 3 * 2, size_t{4} << 20) << "over the client's default limit";

  LiveVideoOptions options;
  options.address = {"video", "127.0.0.1", port};
  options.fps = 10;
  options.stale_after = std::chrono::milliseconds(1500);
  auto live = LiveVideo::Start(options);
  std::optional<StereoFrame> frame;
  ASSERT_TRUE(
      igms::testing::WaitFor("a live pair", [&] { return (frame = live->Newer(0)).has_value(); }));
  EXPECT_EQ(frame->left.cols, 1282);
  EXPECT_EQ(frame->left.rows, 1110);
  EXPECT_EQ(frame->left.channels(), 3);
  EXPECT_EQ(frame->right.cols, 1282);
  EXPECT_FALSE(live->lost());
  // The video server's clock offset, from pings at connection: on one host it is zero
  // within its bound, and the capture-to-receipt latency is taken on it.
  ASSERT_TRUE(
      igms::testing::WaitFor("the clock offset", [&] { return live->stats().clock_pings; }));
  const LiveStats stats = live->stats();
  EXPECT_EQ(stats.clock_pings, 5);
  EXPECT_LE(std::abs(stats.clock_offset_ms), stats.clock_bound_ms + 1e-6);
  ASSERT_TRUE(igms::testing::WaitFor("a frame after the estimate",
                                     [&] { return live->stats().frames > stats.frames; }));
  EXPECT_GT(live->stats().latency_ms, -stats.clock_bound_ms - 1e-6);

  live->MoveOffset(3, -2);
  ASSERT_TRUE(igms::testing::WaitFor("the offset stored", [&] {
    return live->overlay().u_offset_px() == 3 && live->overlay().v_offset_px() == -2;
  }));

  // A frozen session's pair: the grab itself, fetched by its frame id.
  igms::testing::TestClient client(port);
  auto grab = client->CallSync<video::GrabResponse>("igms.video.VideoService.Grab",
                                                    video::GrabRequest(), std::chrono::seconds(5));
  ASSERT_TRUE(grab.ok()) << grab.status.ToString();
  live->FetchGrab(grab.value.frame_id());
  std::optional<StereoFrame> grabbed;
  ASSERT_TRUE(igms::testing::WaitFor("the grabbed pair", [&] {
    return (grabbed = live->Grabbed(grab.value.frame_id())).has_value();
  }));
  EXPECT_EQ(grabbed->left.cols, 1282);
  EXPECT_EQ(grabbed->sequence, LiveVideo::kGrabSequence + grab.value.frame_id());

  server.reset();  // the video server goes away
  ASSERT_TRUE(igms::testing::WaitFor("the video reported lost", [&] { return live->lost(); }));
  EXPECT_TRUE(live->Newer(0)) << "the last frame stays";
}

}  // namespace
}  // namespace igms::control
