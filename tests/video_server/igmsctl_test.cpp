// The video server driven by igmsctl, the lab's generic fake client, as an operator would.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>

#include "tests/support/video_server_process.h"
#include "tests/video_server/test_data.h"

namespace igms::video {
namespace {

using testing::OpenCvData;

struct CtlRun {
  int status = -1;
  std::string output;
};

// Runs igmsctl with `args` (quoted for the shell), capturing stdout and stderr.
CtlRun Igmsctl(uint16_t port, const std::string& args) {
  const std::string command =
      testing::BinDir() + "/igmsctl -p " + std::to_string(port) + " " + args + " 2>&1";
  const igms::testing::ShellRun run = igms::testing::RunShell(command);
  return {run.status, run.out};
}

TEST(VideoServerWithIgmsctl, GrabEdgesOverlayAndLive) {
  IGMS_REQUIRE_OPENCV_DATA();
  testing::ScratchDir scratch;
  testing::ServerProcess server({"--set", "processes.video.files.left=" + OpenCvData("aloeL.jpg"),
                                 "--set", "processes.video.files.right=" + OpenCvData("aloeR.jpg"),
                                 "--set",
                                 "processes.video.overlay_file=" + scratch.File("overlay.yaml")});
  const uint16_t port = server.WaitPort();
  ASSERT_NE(port, 0);

  const CtlRun grab = Igmsctl(port, "call Grab");
  ASSERT_EQ(grab.status, 0) << grab.output;
  std::smatch match;
  ASSERT_TRUE(std::regex_search(grab.output, match, std::regex("\"frame_id\":\"(\\d+)\"")))
      << grab.output;
  const std::string id = match[1];
  EXPECT_NE(grab.output.find("\"width\":1282"), std::string::npos) << grab.output;

  const CtlRun edges = Igmsctl(
      port, "call GetEdges '{\"frame_id\": \"" + id +
                "\", \"side\": \"LEFT\", \"region\": {\"x\": 400, \"y\": 300, \"width\": 64, "
                "\"height\": 64}}'");
  ASSERT_EQ(edges.status, 0) << edges.output;
  EXPECT_NE(edges.output.find("\"edge_count\""), std::string::npos) << edges.output;
  EXPECT_NE(edges.output.find("\"direction_rad\""), std::string::npos);

  // The status names where edges are computed and counts the one edge job, done.
  const CtlRun status = Igmsctl(port, "call GetStatus");
  ASSERT_EQ(status.status, 0) << status.output;
  EXPECT_NE(status.output.find("\"listen_address\":\"127.0.0.1:" + std::to_string(port) + "\""),
            std::string::npos)
      << status.output;
  EXPECT_TRUE(std::regex_search(status.output, std::regex("\"hostname\":\"[^\"]+\"")))
      << status.output;
  EXPECT_NE(status.output.find("\"edge_jobs_done\":\"1\""), std::string::npos) << status.output;
  EXPECT_NE(status.output.find("\"edge_jobs_failed\":\"0\""), std::string::npos);
  EXPECT_NE(status.output.find("\"edge_jobs_in_flight\":0"), std::string::npos);

  // A ping says how far the server's clock is from this host's: one clock here, so no
  // farther than the bound it gives (half the best round trip), however loaded the host.
  const CtlRun ping = Igmsctl(port, "ping --pings 3");
  ASSERT_EQ(ping.status, 0) << ping.output;
  std::smatch offset;
  ASSERT_TRUE(std::regex_search(ping.output, offset,
                                std::regex("clock offset ([+-]\\d+\\.\\d+) ms \\(within "
                                           "[^0-9]*(\\d+\\.\\d+) ms, best of 3 pings\\)")))
      << ping.output;
  EXPECT_LE(std::abs(std::stod(offset[1])), std::stod(offset[2])) << ping.output;
  EXPECT_EQ(ping.output.find("warning"), std::string::npos) << ping.output;

  const CtlRun unknown = Igmsctl(port, "call GetImages '{\"frame_id\": \"12345\"}'");
  EXPECT_EQ(unknown.status, 1) << unknown.output;
  EXPECT_NE(unknown.output.find("NOT_FOUND"), std::string::npos) << unknown.output;

  const CtlRun set = Igmsctl(port,
                             "call SetOverlay '{\"settings\": {\"u_offset_px\": 3, "
                             "\"v_offset_px\": -2, \"key_level\": 61}}'");
  ASSERT_EQ(set.status, 0) << set.output;
  const CtlRun get = Igmsctl(port, "call GetOverlay");
  EXPECT_NE(get.output.find("\"u_offset_px\":3"), std::string::npos) << get.output;
  EXPECT_NE(get.output.find("\"key_level\":61"), std::string::npos) << get.output;

  const CtlRun live =
      Igmsctl(port,
              "subscribe VideoService.Live '{\"fps\": 20, \"width\": 64, \"height\": 48}' "
              "--count 10 -q --timeout 20000");
  EXPECT_EQ(live.status, 0) << live.output;
  EXPECT_NE(live.output.find("10 messages"), std::string::npos) << live.output;
}

}  // namespace
}  // namespace igms::video
