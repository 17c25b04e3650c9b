// igms-video-server as a real process on loopback: every request, eviction, bad input,
// overlay persistence and frame ids across a restart, live video to fast and slow clients.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <future>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/base/clock.h"
#include "common/net/mailbox.h"
#include "common/wire/image_message.h"
#include "igms/video.pb.h"
#include "tests/support/video_server_process.h"
#include "tests/support/wait.h"
#include "tests/video_server/test_data.h"
#include "video_server/edges.h"
#include "video_server/stereo_frame.h"

namespace igms::video {
namespace {

using wire::DecodeProtoImage;

using namespace std::chrono_literals;
using testing::OpenCvData;
using testing::ScratchDir;
using testing::ServerProcess;
using testing::TestClient;

const std::string kService = "igms.video.VideoService.";

std::vector<std::string> FilesArgs(const std::string& left, const std::string& right) {
  return {"--set", "processes.video.backend=files",
          "--set", "processes.video.files.left=" + left,
          "--set", "processes.video.files.right=" + right};
}

cv::Mat Grey(const std::string& name) { return cv::imread(OpenCvData(name), cv::IMREAD_GRAYSCALE); }

bool Same(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

class VideoServerTest : public ::testing::Test {
 protected:
  void SetUp() override { IGMS_REQUIRE_OPENCV_DATA(); }

  void Start(std::vector<std::string> extra = {}) {
    std::vector<std::string> args = FilesArgs(OpenCvData("left01.jpg"), OpenCvData("right01.jpg"));
    args.insert(args.end(),
                {"--set", "processes.video.overlay_file=" + scratch_.File("overlay.yaml")});
    args.insert(args.end(), extra.begin(), extra.end());
    client_.reset();
    server_ = std::make_unique<ServerProcess>(args);
    const uint16_t port = server_->WaitPort();
    ASSERT_NE(port, 0) << "igms-video-server did not start";
    client_ = std::make_unique<TestClient>(port);
    ASSERT_TRUE((*client_)->WaitConnected(5s));
  }

  GrabResponse Grab() {
    auto grab = (*client_)->CallSync<GrabResponse>(kService + "Grab", GrabRequest{}, 10s);
    EXPECT_TRUE(grab.ok()) << grab.status.ToString();
    return grab.value;
  }

  template <class Resp, class Req>
  net::Result<Resp> Call(const std::string& method, const Req& request) {
    return (*client_)->CallSync<Resp>(kService + method, request, 20s);
  }

  ScratchDir scratch_;
  std::unique_ptr<ServerProcess> server_;
  std::unique_ptr<TestClient> client_;
};

TEST_F(VideoServerTest, GrabThenImagesWholeAndByRegion) {
  Start();
  const int64_t before = UnixNs();
  const GrabResponse first = Grab();
  const GrabResponse second = Grab();
  EXPECT_EQ(second.frame_id(), first.frame_id() + 1);
  EXPECT_EQ(first.width(), 640);
  EXPECT_EQ(first.height(), 480);
  EXPECT_EQ(first.channels(), 1);
  EXPECT_GE(first.left_capture_unix_ns(), before);
  EXPECT_LE(first.left_capture_unix_ns(), second.left_capture_unix_ns());
  EXPECT_EQ(first.pose().joints_rad_size(), 3);
  EXPECT_FALSE(first.pose().from_platform());
  for (double joint : first.pose().joints_rad()) EXPECT_EQ(joint, 0.0);

  GetImagesRequest request;
  request.set_frame_id(first.frame_id());
  auto whole = Call<GetImagesResponse>("GetImages", request);
  ASSERT_TRUE(whole.ok()) << whole.status.ToString();
  EXPECT_EQ(whole.value.left().encoding(), PNG);  // the configured default
  EXPECT_TRUE(Same(DecodeProtoImage(whole.value.left()), Grey("left01.jpg")));
  EXPECT_TRUE(Same(DecodeProtoImage(whole.value.right()), Grey("right01.jpg")));
  EXPECT_EQ(whole.value.left_capture_unix_ns(), first.left_capture_unix_ns());

  request.set_side(RIGHT);
  request.set_encoding(RAW);
  request.mutable_region()->set_x(100);
  request.mutable_region()->set_y(40);
  request.mutable_region()->set_width(200);
  request.mutable_region()->set_height(120);
  auto part = Call<GetImagesResponse>("GetImages", request);
  ASSERT_TRUE(part.ok()) << part.status.ToString();
  EXPECT_FALSE(part.value.has_left());
  EXPECT_EQ(part.value.right().data().size(), 200u * 120u);
  EXPECT_EQ(part.value.right().region().x(), 100);
  EXPECT_TRUE(
      Same(DecodeProtoImage(part.value.right()), Grey("right01.jpg")(cv::Rect(100, 40, 200, 120))));
}

TEST_F(VideoServerTest, EdgesAreTheDetectorsOutputWithDirectionsForTheRegion) {
  Start({"--set", "processes.video.edges.low=40", "--set", "processes.video.edges.high=120"});
  const GrabResponse grab = Grab();
  GetEdgesRequest request;
  request.set_frame_id(grab.frame_id());
  request.set_side(LEFT);
  request.mutable_region()->set_x(150);
  request.mutable_region()->set_y(100);
  request.mutable_region()->set_width(300);
  request.mutable_region()->set_height(250);
  auto edges = Call<GetEdgesResponse>("GetEdges", request);
  ASSERT_TRUE(edges.ok()) << edges.status.ToString();

  EdgeOptions options;
  options.low_threshold = 40;
  options.high_threshold = 120;
  const EdgeImage expected = DetectEdges(Grey("left01.jpg"), options);
  const cv::Rect rect(150, 100, 300, 250);
  EXPECT_TRUE(Same(DecodeProtoImage(edges.value.left().edges()), expected.edges(rect)));
  const std::vector<float> directions = DirectionsInRegion(expected, rect);
  ASSERT_EQ(edges.value.left().direction_rad_size(), static_cast<int>(directions.size()));
  EXPECT_GT(directions.size(), 500u);
  for (size_t i = 0; i < directions.size(); ++i) {
    ASSERT_EQ(edges.value.left().direction_rad(static_cast<int>(i)), directions[i]) << i;
  }
  EXPECT_EQ(edges.value.left().edge_count(), static_cast<int>(directions.size()));
  EXPECT_FALSE(edges.value.has_right());
  EXPECT_NEAR(edges.value.parameters().sigma_px(), kDefaultEdgeSigma, 1e-12);
  EXPECT_EQ(edges.value.parameters().low_threshold(), 40);
  EXPECT_GT(edges.value.ready_ms(), 0.0);
}

TEST_F(VideoServerTest, EvictedAndUnknownFramesAndBadInputAreErrorsAndTheServerGoesOn) {
  Start({"--set", "processes.video.store_capacity=2"});
  const GrabResponse a = Grab();
  Grab();
  const GrabResponse c = Grab();
  GetEdgesRequest edges;
  edges.set_frame_id(a.frame_id());
  auto evicted = Call<GetEdgesResponse>("GetEdges", edges);
  EXPECT_EQ(evicted.status.code, igms::NOT_FOUND);
  EXPECT_NE(evicted.status.message.find("evicted"), std::string::npos) << evicted.status.message;

  GetImagesRequest images;
  images.set_frame_id(c.frame_id() + 1000);
  auto unknown = Call<GetImagesResponse>("GetImages", images);
  EXPECT_EQ(unknown.status.code, igms::NOT_FOUND);
  EXPECT_NE(unknown.status.message.find("no such frame"), std::string::npos);

  images.set_frame_id(c.frame_id());
  images.mutable_region()->set_x(600);
  images.mutable_region()->set_width(100);
  images.mutable_region()->set_height(10);
  auto outside = Call<GetImagesResponse>("GetImages", images);
  EXPECT_EQ(outside.status.code, igms::BAD_REQUEST);
  EXPECT_NE(outside.status.message.find("outside"), std::string::npos);

  edges.set_frame_id(c.frame_id());
  edges.set_timeout_ms(1'000'000);
  EXPECT_EQ(Call<GetEdgesResponse>("GetEdges", edges).status.code, igms::BAD_REQUEST);

  // A payload that is not a GetImagesRequest.
  std::promise<net::Status> garbage;
  (*client_)->CallRaw(
      kService + "GetImages", std::string("\xff\xff\xff\xff", 4), 5s,
      [&](const net::Status& status, std::string_view) { garbage.set_value(status); });
  EXPECT_EQ(garbage.get_future().get().code, igms::BAD_REQUEST);

  SetOverlayRequest overlay;
  overlay.mutable_settings()->set_key_level(999);
  EXPECT_EQ(Call<SetOverlayResponse>("SetOverlay", overlay).status.code, igms::BAD_REQUEST);

  // Still serving.
  edges.set_timeout_ms(0);
  EXPECT_TRUE(Call<GetEdgesResponse>("GetEdges", edges).ok());
  auto status = Call<StatusResponse>("GetStatus", StatusRequest{});
  ASSERT_TRUE(status.ok());
  EXPECT_EQ(status.value.frames_held(), 2u);
  EXPECT_EQ(status.value.evictions(), 1u);
  EXPECT_EQ(status.value.newest_frame_id(), c.frame_id());
}

TEST_F(VideoServerTest, OverlaySurvivesARestartAndFrameIdsNeverRepeat) {
  Start();
  auto initial = Call<GetOverlayResponse>("GetOverlay", GetOverlayRequest{});
  ASSERT_TRUE(initial.ok());
  EXPECT_EQ(initial.value.settings().key_level(), 60);
  SetOverlayRequest set;
  set.mutable_settings()->set_u_offset_px(-14);
  set.mutable_settings()->set_v_offset_px(9);
  set.mutable_settings()->set_key_level(75);
  ASSERT_TRUE(Call<SetOverlayResponse>("SetOverlay", set).ok());
  std::vector<uint64_t> ids;
  ids.reserve(5);
  for (int i = 0; i < 5; ++i) ids.push_back(Grab().frame_id());

  EXPECT_EQ(server_->Stop(), 0);
  Start();
  auto after = Call<GetOverlayResponse>("GetOverlay", GetOverlayRequest{});
  ASSERT_TRUE(after.ok());
  EXPECT_EQ(after.value.settings().u_offset_px(), -14);
  EXPECT_EQ(after.value.settings().v_offset_px(), 9);
  EXPECT_EQ(after.value.settings().key_level(), 75);
  const uint64_t next = Grab().frame_id();
  EXPECT_GT(next, ids.back());
  GetImagesRequest old;
  old.set_frame_id(ids.back());
  auto gone = Call<GetImagesResponse>("GetImages", old);
  EXPECT_EQ(gone.status.code, igms::NOT_FOUND);
  EXPECT_NE(gone.status.message.find("since the video server started"), std::string::npos);
}

TEST_F(VideoServerTest, LiveVideoToAFastAndASlowSubscriber) {
  Start();
  // What a subscriber took, by the server's stamps: the capture counter, and how long the
  // server held each frame between capture and send.
  struct Received {
    std::mutex mutex;
    std::vector<uint64_t> sequences;
    std::vector<double> held_ms;
    // For the slow one: how many captures behind the fast subscriber's newest each frame it
    // took was, when it took it.
    std::vector<int64_t> behind;
    size_t size() {
      std::lock_guard lock(mutex);
      return sequences.size();
    }
  };
  Received fast, slow;
  LiveRequest request;
  request.set_fps(30);
  request.set_width(320);
  request.set_height(240);
  request.set_encoding(RAW);
  const cv::Mat expected_left = [] {
    cv::Mat small;
    cv::resize(Grey("left01.jpg"), small, cv::Size(320, 240), 0, 0, cv::INTER_AREA);
    return small;
  }();
  std::atomic<bool> left_matches{true};
  std::atomic<uint64_t> newest{0};
  (*client_)->Subscribe<LiveFrame>(kService + "Live", request, [&](const LiveFrame& frame) {
    if (!Same(DecodeProtoImage(frame.left()), expected_left)) left_matches = false;
    newest = frame.sequence();
    std::lock_guard lock(fast.mutex);
    fast.sequences.push_back(frame.sequence());
    fast.held_ms.push_back(static_cast<double>(frame.send_unix_ns() - frame.capture_unix_ns()) /
                           1e6);
  });
  // A slow subscriber as a real client is written: its network thread hands frames to a
  // one-frame mailbox, and a render loop that needs 250 ms a frame takes the newest.
  TestClient slow_client(server_->WaitPort());
  ASSERT_TRUE(slow_client->WaitConnected(5s));
  request.set_width(0);
  request.set_height(0);
  net::Mailbox<LiveFrame> mailbox(1);
  slow_client->Subscribe<LiveFrame>(kService + "Live", request,
                                    [&](const LiveFrame& frame) { mailbox.Push(frame); });
  std::atomic<bool> stop{false};
  std::thread render_loop([&] {
    while (!stop) {
      std::optional<LiveFrame> frame;
      if (!igms::testing::WaitUntil([&] { return stop || (frame = mailbox.TryPop()); })) continue;
      if (!frame) continue;
      {
        std::lock_guard lock(slow.mutex);
        slow.sequences.push_back(frame->sequence());
        slow.held_ms.push_back(
            static_cast<double>(frame->send_unix_ns() - frame->capture_unix_ns()) / 1e6);
        slow.behind.push_back(static_cast<int64_t>(newest) -
                              static_cast<int64_t>(frame->sequence()));
      }
      std::this_thread::sleep_for(250ms);  // rendering
    }
  });
  // A client that stops reading altogether (its network thread blocked) must not slow the
  // others either.
  TestClient stalled_client(server_->WaitPort());
  ASSERT_TRUE(stalled_client->WaitConnected(5s));
  stalled_client->Subscribe<LiveFrame>(kService + "Live", request, [](const LiveFrame&) {
    std::this_thread::sleep_for(1s);  // a network thread that hardly ever reads
  });
  // Twelve frames rendered by the slow subscriber: about 3 s of its loop.
  const bool rendered = igms::testing::WaitUntil([&] { return slow.size() >= 12; }, 60s);
  stop = true;
  render_loop.join();
  ASSERT_TRUE(rendered) << "the slow subscriber rendered " << slow.size() << " frames";

  std::scoped_lock lock(fast.mutex, slow.mutex);
  EXPECT_TRUE(left_matches);
  for (size_t i = 1; i < fast.sequences.size(); ++i) {
    EXPECT_GT(fast.sequences[i], fast.sequences[i - 1]);
  }
  // Over the captures the slow subscriber's frames span, the fast one got many more: it is
  // not held back by the slow or the stalled one (30 a second asked, 250 ms a slow frame).
  const uint64_t from = slow.sequences.front(), to = slow.sequences.back();
  const auto fast_meanwhile = std::count_if(fast.sequences.begin(), fast.sequences.end(),
                                            [&](uint64_t s) { return s >= from && s <= to; });
  EXPECT_GT(static_cast<size_t>(fast_meanwhile), 2 * slow.sequences.size());
  // The slow subscriber skips frames rather than queueing them: the captures it takes lie
  // far apart, and each is fresh: a queue would leave it one more frame behind the newest
  // with every frame it renders (the bound leaves room for a loaded machine).
  EXPECT_GT(to - from, 3 * (slow.sequences.size() - 1));
  std::vector<int64_t> behind = slow.behind;
  std::sort(behind.begin(), behind.end());
  EXPECT_LE(behind[behind.size() / 2], 3);
  EXPECT_LE(slow.behind.back(), 8);
  // The server sends every frame soon after its capture, to each subscriber.
  for (std::vector<double>* held : {&fast.held_ms, &slow.held_ms}) {
    std::vector<double> sorted = *held;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_LT(sorted[sorted.size() / 2], 100.0);
  }
}

TEST_F(VideoServerTest, BadLiveRequestIsRefused) {
  Start();
  LiveRequest request;
  request.set_fps(5000);
  std::promise<net::Status> refused;
  (*client_)->Subscribe<LiveFrame>(
      kService + "Live", request, [](const LiveFrame&) {},
      [&](const net::Status& status) { refused.set_value(status); });
  auto future = refused.get_future();
  ASSERT_EQ(future.wait_for(10s), std::future_status::ready);
  const net::Status status = future.get();
  EXPECT_EQ(status.code, igms::BAD_REQUEST);
  EXPECT_NE(status.message.find("fps"), std::string::npos);
}

TEST(VideoServerProcess, MissingCameraGrabIsUnavailableNotAHang) {
  ServerProcess server({"--set", "processes.video.backend=camera", "--set",
                        "processes.video.camera.left=/dev/video97", "--set",
                        "processes.video.camera.right=/dev/video98", "--set",
                        "processes.video.camera.frame_timeout_ms=500"});
  const uint16_t port = server.WaitPort();
  ASSERT_NE(port, 0);
  TestClient client(port);
  // A hang would end in the call's own deadline, with another code and no device named.
  auto grab = client->CallSync<GrabResponse>(kService + "Grab", GrabRequest{}, 10s);
  EXPECT_EQ(grab.status.code, igms::UNAVAILABLE);
  EXPECT_NE(grab.status.message.find("/dev/video97"), std::string::npos) << grab.status.message;
}

TEST(VideoServerProcess, BadConfigurationExitsWithAClearStatus) {
  ServerProcess missing(FilesArgs("/nonexistent/left.png", "/nonexistent/right.png"));
  EXPECT_EQ(missing.Wait(20s), 2);
  ServerProcess unknown({"--set", "processes.video.backend=telepathy"});
  EXPECT_EQ(unknown.Wait(20s), 2);
  ServerProcess bad_edges({"--set", "processes.video.files.left=" + OpenCvData("left01.jpg"),
                           "--set", "processes.video.files.right=" + OpenCvData("right01.jpg"),
                           "--set", "processes.video.edges.low=500"});
  EXPECT_EQ(bad_edges.Wait(20s), 2);
}

}  // namespace
}  // namespace igms::video
