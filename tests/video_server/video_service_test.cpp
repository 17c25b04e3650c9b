// The service in-process: edge waits that time out, and shutting down with work in flight.
#include "video_server/video_service.h"

#include <gtest/gtest.h>

#include <atomic>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <future>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "tests/support/io_thread.h"
#include "tests/video_server/test_data.h"
#include "video_server/files_capture.h"

namespace igms::video {
namespace {

using namespace std::chrono_literals;
using testing::OpenCvData;

using igms::testing::IoThread;

std::unique_ptr<CaptureBackend> Aloe() {
  FilesCaptureOptions options{OpenCvData("aloeL.jpg"), OpenCvData("aloeR.jpg")};
  options.colour = true;
  return OpenFilesCapture(options).backend;
}

TEST(VideoService, EdgeWaitTimesOutWhenDetectionIsSlowerThanTheRequestAllows) {
  IGMS_REQUIRE_OPENCV_DATA();
  IoThread io;
  VideoServiceOptions options;
  options.edge_threads = 1;
  options.edges.sigma = 40;  // a very wide filter: detection takes a while
  VideoService service(io.io(), Aloe(), options, {});
  GrabResponse grab;
  ASSERT_TRUE(service.Grab(grab).ok());
  GetEdgesRequest request;
  request.set_frame_id(grab.frame_id());
  request.set_timeout_ms(1);
  std::promise<net::Status> answer;
  service.GetEdges(request, [&](const net::Status& status, const GetEdgesResponse&) {
    answer.set_value(status);
  });
  const net::Status status = answer.get_future().get();
  EXPECT_EQ(status.code, igms::TIMEOUT);
  EXPECT_NE(status.message.find("not ready within 1 ms"), std::string::npos) << status.message;
  // Later the edges are there for whoever waits long enough.
  request.set_timeout_ms(60000);
  std::promise<net::Status> later;
  service.GetEdges(request, [&](const net::Status& s, const GetEdgesResponse& r) {
    EXPECT_EQ(r.left().edges().width(), 1282);
    EXPECT_EQ(r.left().edges().height(), 1110);
    later.set_value(s);
  });
  EXPECT_TRUE(later.get_future().get().ok());
}

TEST(VideoService, ShutsDownCleanlyWithGrabsEdgesAndRequestsInFlight) {
  IGMS_REQUIRE_OPENCV_DATA();
  std::atomic<int> answered{0};
  {
    IoThread io;
    VideoServiceOptions options;
    options.store_capacity = 3;
    VideoService service(io.io(), Aloe(), options, {});
    for (int i = 0; i < 8; ++i) {
      GrabResponse grab;
      ASSERT_TRUE(service.Grab(grab).ok());
      GetEdgesRequest request;
      request.set_frame_id(grab.frame_id());
      service.GetEdges(request, [&](const net::Status&, const GetEdgesResponse&) { ++answered; });
    }
    // The service goes away here with detection and encoding still queued.
  }
  // Every request was answered once at most; none crashed the process.
  EXPECT_LE(answered.load(), 8);
}

}  // namespace
}  // namespace igms::video
