// The frame store, the frame ids and the edge pipeline, on real images.
#include "video_server/frame_store.h"

#include <gtest/gtest.h>

#include <atomic>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "tests/support/wait.h"
#include "tests/video_server/test_data.h"
#include "video_server/edge_pipeline.h"
#include "video_server/frame_id.h"

namespace igms::video {
namespace {

using namespace std::chrono_literals;
using testing::OpenCvData;

StereoImages Pair(int width = 64, int height = 48, int value = 0) {
  StereoImages images;
  images.left = cv::Mat(height, width, CV_8UC1, cv::Scalar(value));
  images.right = images.left.clone();
  return images;
}

TEST(FrameIds, AreConsecutiveAndLaterRunsStartHigher) {
  FrameIdSource first_run;
  const uint64_t a = first_run.Next(), b = first_run.Next();
  EXPECT_EQ(a, first_run.first());
  EXPECT_EQ(b, a + 1);
  // Microseconds since the epoch: a plausible wall-clock time.
  EXPECT_GT(a, 1'600'000'000'000'000ull);
  for (int i = 0; i < 1000; ++i) first_run.Next();
  // A restart once the clock has passed the ids handed out.
  const uint64_t handed_out = first_run.Next();
  ASSERT_TRUE(igms::testing::WaitUntil([&] { return FrameIdSource().first() > handed_out; }));
  FrameIdSource second_run;
  EXPECT_GT(second_run.first(), first_run.Next());
}

TEST(FrameStore, KeepsTheLastNAndExplainsMisses) {
  FrameStore store(3, 100);
  for (uint64_t id = 100; id < 106; ++id) store.Insert(id, Pair(64, 48, static_cast<int>(id)));
  EXPECT_EQ(store.size(), 3u);
  EXPECT_EQ(store.evictions(), 3u);
  for (uint64_t id = 103; id < 106; ++id) {
    FrameLookup found = store.Find(id);
    ASSERT_TRUE(found.record) << found.error;
    EXPECT_EQ(found.record->images().left.at<uint8_t>(0, 0), id);
  }
  FrameLookup evicted = store.Find(101);
  EXPECT_FALSE(evicted.record);
  EXPECT_TRUE(evicted.evicted);
  EXPECT_NE(evicted.error.find("evicted"), std::string::npos) << evicted.error;
  EXPECT_NE(evicted.error.find("last 3"), std::string::npos) << evicted.error;
  FrameLookup future = store.Find(999);
  EXPECT_FALSE(future.record);
  EXPECT_FALSE(future.evicted);
  EXPECT_NE(future.error.find("no such frame"), std::string::npos) << future.error;
  FrameLookup earlier_run = store.Find(42);
  EXPECT_NE(earlier_run.error.find("since the video server started"), std::string::npos)
      << earlier_run.error;
  EXPECT_EQ(store.Newest()->id(), 105u);
  EXPECT_THROW(store.Insert(104, Pair()), std::logic_error);
}

TEST(FrameStore, MemoryIsBoundedByCapacity) {
  FrameStore store(4, 1);
  const size_t pair_bytes = size_t{2} * 640 * 480;
  for (uint64_t id = 1; id <= 50; ++id) store.Insert(id, Pair(640, 480));
  EXPECT_EQ(store.bytes(), 4 * pair_bytes);
}

TEST(FrameRecord, CallbacksRunOnceWhenEdgesArrive) {
  FrameRecord record(7, Pair());
  EXPECT_EQ(record.edges(), nullptr);
  EXPECT_EQ(record.WaitEdges(10ms), nullptr);
  int early = 0, late = 0;
  record.OnEdgesReady([&](auto edges) { early += edges != nullptr; });
  auto edges = std::make_shared<StereoEdges>();
  std::thread producer([&] {
    std::this_thread::sleep_for(20ms);
    record.SetEdges(edges);
  });
  EXPECT_EQ(record.WaitEdges(5s), edges);
  producer.join();
  record.OnEdgesReady([&](auto ready) { late += ready == edges; });
  EXPECT_EQ(early, 1);
  EXPECT_EQ(late, 1);
  EXPECT_THROW(record.SetEdges(edges), std::logic_error);
}

TEST(EdgePipeline, EdgesOfEveryGrabAreReadyWithoutBeingAsked) {
  IGMS_REQUIRE_OPENCV_DATA();
  StereoImages images;
  images.left = cv::imread(OpenCvData("left01.jpg"), cv::IMREAD_GRAYSCALE);
  images.right = cv::imread(OpenCvData("right01.jpg"), cv::IMREAD_GRAYSCALE);
  EdgeOptions options;
  options.low_threshold = 40;
  options.high_threshold = 120;
  EdgePipeline pipeline(options, 2);
  FrameStore store(8, 1);
  std::vector<std::shared_ptr<FrameRecord>> records;
  for (uint64_t id = 1; id <= 4; ++id) {
    records.push_back(store.Insert(id, images));
    pipeline.Start(records.back());
  }
  const EdgeImage expected_left = DetectEdges(images.left, options);
  const EdgeImage expected_right = DetectEdges(images.right, options);
  for (const auto& record : records) {
    auto edges = record->WaitEdges(30s);
    ASSERT_TRUE(edges);
    EXPECT_EQ(edges->error, "");
    EXPECT_EQ(edges->options.low_threshold, 40);
    EXPECT_EQ(cv::countNonZero(edges->left.edges != expected_left.edges), 0);
    EXPECT_EQ(cv::countNonZero(edges->right.edges != expected_right.edges), 0);
    EXPECT_EQ(edges->left.direction_rad, expected_left.direction_rad);
    EXPECT_GT(edges->ready_ms, 0.0);
    EXPECT_GE(edges->ready_ms, edges->left_ms);
  }
  EXPECT_THROW(EdgePipeline(EdgeOptions{.sigma = -2}, 1), std::invalid_argument);
}

TEST(EdgePipeline, FramesEvictedBeforeTheirTurnAreSkipped) {
  FrameStore store(1, 1);
  EdgePipeline pipeline({}, 1);
  // A burst of grabs far faster than the single worker detects edges on full-size images:
  // the store keeps only the newest, so every other frame is evicted while its detection
  // still waits in the queue.
  std::vector<std::weak_ptr<FrameRecord>> burst;
  std::shared_ptr<FrameRecord> last;
  for (uint64_t id = 1; id <= 20; ++id) {
    last = store.Insert(id, Pair(1920, 1080, 0));
    pipeline.Start(last);
    burst.push_back(last);
  }
  last.reset();
  EXPECT_EQ(store.size(), 1u);
  EXPECT_EQ(store.evictions(), 19u);
  // The queue holds no evicted frame alive: all are gone, but for the one the worker may
  // be detecting edges on right now. Nobody can ask for them any more, so they are skipped.
  int alive = 0;
  for (size_t i = 0; i + 1 < burst.size(); ++i) alive += burst[i].expired() ? 0 : 1;
  EXPECT_LE(alive, 1);
  for (uint64_t id = 1; id < 20; ++id) EXPECT_TRUE(store.Find(id).evicted) << id;
  // The frame still in the store gets its edges.
  const auto kept = store.Newest();
  ASSERT_TRUE(kept);
  EXPECT_EQ(kept->id(), 20u);
  const auto edges = kept->WaitEdges(30s);
  ASSERT_TRUE(edges);
  EXPECT_EQ(edges->error, "");
  EXPECT_FALSE(edges->left.edges.empty());
}

}  // namespace
}  // namespace igms::video
