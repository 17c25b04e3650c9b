// The capture backends on real images and real video through cv::VideoCapture.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "common/base/clock.h"
#include "tests/video_server/test_data.h"
#include "video_server/camera_capture.h"
#include "video_server/files_capture.h"

namespace igms::video {
namespace {

using testing::OpenCvData;
using Clock = std::chrono::steady_clock;

bool SameImage(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

TEST(FilesCapture, SinglePairIsReturnedOnEveryGrabWithTimeAndPose) {
  IGMS_REQUIRE_OPENCV_DATA();
  FilesOpenResult open = OpenFilesCapture({OpenCvData("left01.jpg"), OpenCvData("right01.jpg")});
  ASSERT_TRUE(open.backend) << open.error;
  const cv::Mat left = cv::imread(OpenCvData("left01.jpg"), cv::IMREAD_GRAYSCALE);
  const cv::Mat right = cv::imread(OpenCvData("right01.jpg"), cv::IMREAD_GRAYSCALE);
  PoseStamp pose;
  pose.joints_rad = {0.25, 0.0, 0.0};
  pose.from_platform = true;
  for (int i = 0; i < 3; ++i) {
    const int64_t before = UnixNs();
    CaptureResult grab = open.backend->Capture(pose);
    ASSERT_TRUE(grab.ok()) << grab.error;
    EXPECT_EQ(grab.images->left.type(), CV_8UC1);
    EXPECT_EQ(grab.images->left.size(), cv::Size(640, 480));
    EXPECT_TRUE(SameImage(grab.images->left, left));
    EXPECT_TRUE(SameImage(grab.images->right, right));
    EXPECT_GE(grab.images->left_capture_unix_ns, before);
    EXPECT_LE(grab.images->left_capture_unix_ns, UnixNs());
    EXPECT_EQ(grab.images->pose.joints_rad[0], 0.25);
    EXPECT_TRUE(grab.images->pose.from_platform);
  }
  EXPECT_NE(open.backend->Describe().find("left01.jpg"), std::string::npos);
}

TEST(FilesCapture, ColourAloePairKeepsItsSizeAndChannels) {
  IGMS_REQUIRE_OPENCV_DATA();
  FilesCaptureOptions options{OpenCvData("aloeL.jpg"), OpenCvData("aloeR.jpg")};
  options.colour = true;
  FilesOpenResult open = OpenFilesCapture(options);
  ASSERT_TRUE(open.backend) << open.error;
  CaptureResult grab = open.backend->Capture({});
  ASSERT_TRUE(grab.ok()) << grab.error;
  EXPECT_EQ(grab.images->left.size(), cv::Size(1282, 1110));
  EXPECT_EQ(grab.images->left.type(), CV_8UC3);
  EXPECT_TRUE(SameImage(grab.images->right, cv::imread(OpenCvData("aloeR.jpg"))));
  EXPECT_TRUE(grab.images->pose.IsZero());
  EXPECT_FALSE(grab.images->pose.from_platform);
}

TEST(FilesCapture, NumberedSequenceSkipsTheMissingPairAndWraps) {
  IGMS_REQUIRE_OPENCV_DATA();
  FilesOpenResult open =
      OpenFilesCapture({OpenCvData("left%02d.jpg"), OpenCvData("right%02d.jpg"), 0, 99});
  ASSERT_TRUE(open.backend) << open.error;
  EXPECT_NE(open.backend->Describe().find("13 pairs"), std::string::npos)
      << open.backend->Describe();
  const std::vector<int> expected = {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 14, 1, 2};
  for (int index : expected) {
    CaptureResult grab = open.backend->Capture({});
    ASSERT_TRUE(grab.ok()) << grab.error;
    const std::string left = OpenCvData(*FormatFilePattern("left%02d.jpg", index));
    const std::string right = OpenCvData(*FormatFilePattern("right%02d.jpg", index));
    EXPECT_TRUE(SameImage(grab.images->left, cv::imread(left, cv::IMREAD_GRAYSCALE))) << left;
    EXPECT_TRUE(SameImage(grab.images->right, cv::imread(right, cv::IMREAD_GRAYSCALE))) << right;
  }
}

TEST(FilesCapture, BadInputGivesAClearError) {
  IGMS_REQUIRE_OPENCV_DATA();
  FilesOpenResult missing = OpenFilesCapture({OpenCvData("left01.jpg"), "/nonexistent/r.png"});
  EXPECT_FALSE(missing.backend);
  EXPECT_NE(missing.error.find("/nonexistent/r.png"), std::string::npos) << missing.error;

  FilesOpenResult mismatch = OpenFilesCapture({OpenCvData("left01.jpg"), OpenCvData("aloeR.jpg")});
  EXPECT_FALSE(mismatch.backend);
  EXPECT_NE(mismatch.error.find("must match"), std::string::npos) << mismatch.error;

  FilesOpenResult not_image =
      OpenFilesCapture({OpenCvData("stereo_calib.xml"), OpenCvData("right01.jpg")});
  EXPECT_FALSE(not_image.backend);
  EXPECT_NE(not_image.error.find("stereo_calib.xml"), std::string::npos) << not_image.error;

  EXPECT_FALSE(OpenFilesCapture({OpenCvData("left%02d%d.jpg"), "right%02d.jpg"}).backend);
  EXPECT_FALSE(OpenFilesCapture({OpenCvData("left%02s.jpg"), "right%02d.jpg"}).backend);
  EXPECT_FALSE(OpenFilesCapture({OpenCvData("left%02d.jpg"), OpenCvData("right01.jpg")}).backend);
  FilesOpenResult none =
      OpenFilesCapture({OpenCvData("left%02d.jpg"), OpenCvData("right%02d.jpg"), 20, 30});
  EXPECT_FALSE(none.backend);
  EXPECT_NE(none.error.find("no stereo pair"), std::string::npos) << none.error;
  EXPECT_FALSE(OpenFilesCapture({"", ""}).backend);
}

TEST(FilesCapture, PatternFormatting) {
  EXPECT_EQ(FormatFilePattern("a%02d.png", 7), "a07.png");
  EXPECT_EQ(FormatFilePattern("a%d.png", 123), "a123.png");
  EXPECT_EQ(FormatFilePattern("100%%_%3d", 5), "100%_  5");
  EXPECT_FALSE(FormatFilePattern("plain.png", 1));
  EXPECT_FALSE(FormatFilePattern("%d%d", 1));
  EXPECT_FALSE(FormatFilePattern("%x", 1));
  EXPECT_FALSE(FormatFilePattern("%", 1));
}

TEST(RenderCapture, StampsTimeAndPoseAndRejectsBadOutput) {
  int calls = 0;
  RenderCapture good("sim: test", [&](const PoseStamp& pose) {
    ++calls;
    StereoImages images;
    images.left = cv::Mat(48, 64, CV_8UC1, cv::Scalar(static_cast<int>(pose.joints_rad[0] * 100)));
    images.right = images.left.clone();
    return CaptureResult::Ok(images);
  });
  PoseStamp pose;
  pose.joints_rad = {0.5, 0.0, 0.0};
  const int64_t before = UnixNs();
  CaptureResult grab = good.Capture(pose);
  ASSERT_TRUE(grab.ok()) << grab.error;
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(grab.images->left.at<uint8_t>(0, 0), 50);
  EXPECT_GE(grab.images->left_capture_unix_ns, before);
  EXPECT_EQ(grab.images->right_capture_unix_ns, grab.images->left_capture_unix_ns);
  EXPECT_EQ(grab.images->pose.joints_rad[0], 0.5);

  RenderCapture mismatched("sim: bad", [](const PoseStamp&) {
    StereoImages images;
    images.left = cv::Mat(48, 64, CV_8UC1, cv::Scalar(0));
    images.right = cv::Mat(48, 65, CV_8UC1, cv::Scalar(0));
    return CaptureResult::Ok(images);
  });
  EXPECT_NE(mismatched.Capture({}).error.find("must match"), std::string::npos);
  RenderCapture failing("sim: fails",
                        [](const PoseStamp&) { return CaptureResult::Error("no scene"); });
  EXPECT_EQ(failing.Capture({}).error, "no scene");
}

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

TEST(CameraCapture, ReadsTwoVideoDevicesWithFreshTimestamps) {
  IGMS_REQUIRE_OPENCV_DATA();
  CameraCaptureOptions options;
  options.left = OpenCvData("Megamind.avi");
  options.right = OpenCvData("Megamind.avi");
  options.pace_fps = 100;
  options.frame_timeout = std::chrono::milliseconds(5000);
  std::string error;
  auto camera = MakeCameraCapture(options, &error);
  ASSERT_TRUE(camera) << error;
  int64_t previous = 0;
  for (int i = 0; i < 5; ++i) {
    const int64_t before = UnixNs();
    CaptureResult grab = camera->Capture({});
    ASSERT_TRUE(grab.ok()) << grab.error;
    EXPECT_EQ(grab.images->left.type(), CV_8UC1);
    EXPECT_EQ(grab.images->left.size(), grab.images->right.size());
    EXPECT_GT(grab.images->left.cols, 100);
    // A frame read after the grab began, newer than the last grab's.
    EXPECT_GE(grab.images->left_capture_unix_ns, before);
    EXPECT_GE(grab.images->right_capture_unix_ns, before);
    EXPECT_GT(grab.images->left_capture_unix_ns, previous);
    previous = grab.images->left_capture_unix_ns;
  }
}

TEST(CameraCapture, SideBySideDeviceIsSplitInHalves) {
  IGMS_REQUIRE_OPENCV_DATA();
  CameraCaptureOptions options;
  options.left = OpenCvData("Megamind.avi");
  options.side_by_side = true;
  options.colour = true;
  options.pace_fps = 100;
  options.frame_timeout = std::chrono::milliseconds(5000);
  std::string error;
  auto camera = MakeCameraCapture(options, &error);
  ASSERT_TRUE(camera) << error;
  // The movie opens on black frames; somewhere in its first frames the halves differ, so
  // the split did not duplicate one side.
  bool halves_differ = false;
  for (int i = 0; i < 40 && !halves_differ; ++i) {
    CaptureResult grab = camera->Capture({});
    ASSERT_TRUE(grab.ok()) << grab.error;
    EXPECT_EQ(grab.images->left.type(), CV_8UC3);
    EXPECT_EQ(grab.images->left.size(), grab.images->right.size());
    EXPECT_EQ(grab.images->left_capture_unix_ns, grab.images->right_capture_unix_ns);
    halves_differ = cv::norm(grab.images->left, grab.images->right, cv::NORM_L1) > 0.0;
  }
  EXPECT_TRUE(halves_differ);
}

TEST(CameraCapture, MissingDeviceIsAClearErrorWithinTheTimeoutAndIsRetried) {
  IGMS_REQUIRE_OPENCV_DATA();
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("igms_camera_" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  const std::string late = (folder / "late.avi").string();
  CameraCaptureOptions options;
  options.left = late;
  options.right = OpenCvData("Megamind.avi");
  options.pace_fps = 100;
  options.frame_timeout = std::chrono::milliseconds(1500);
  options.retry_interval = std::chrono::milliseconds(100);
  std::string error;
  auto camera = MakeCameraCapture(options, &error);
  ASSERT_TRUE(camera) << error;

  // OpenCV tries each of its backends on the first open, which can take a while; every
  // grab returns within its timeout whatever the device does.
  // Until that first attempt fails, the error says it is still opening the device.
  CaptureResult grab;
  for (int attempt = 0; attempt < 12; ++attempt) {
    const auto start = Clock::now();
    grab = camera->Capture({});
    EXPECT_LT(SecondsSince(start), 2.5);
    ASSERT_FALSE(grab.ok());
    EXPECT_NE(grab.error.find(late), std::string::npos) << grab.error;
    if (grab.error.find("cannot open") != std::string::npos) break;
  }
  EXPECT_NE(grab.error.find("left camera " + late), std::string::npos) << grab.error;
  EXPECT_NE(grab.error.find("cannot open"), std::string::npos) << grab.error;
  EXPECT_NE(grab.error.find("retrying"), std::string::npos) << grab.error;

  // The device appears: the reader's retry opens it and grabs succeed again.
  std::filesystem::copy_file(OpenCvData("Megamind.avi"), late);
  bool recovered = false;
  for (int attempt = 0; attempt < 30 && !recovered; ++attempt) recovered = camera->Capture({}).ok();
  EXPECT_TRUE(recovered);
  camera.reset();
  std::filesystem::remove_all(folder);
}

TEST(CameraCapture, NoSuchDeviceIndexNeverHangs) {
  CameraCaptureOptions options;
  options.left = "/dev/video97";
  options.right = "/dev/video98";
  options.frame_timeout = std::chrono::milliseconds(200);
  std::string error;
  auto camera = MakeCameraCapture(options, &error);
  ASSERT_TRUE(camera) << error;
  const auto start = Clock::now();
  for (int i = 0; i < 3; ++i) {
    CaptureResult grab = camera->Capture({});
    EXPECT_FALSE(grab.ok());
    EXPECT_NE(grab.error.find("/dev/video97"), std::string::npos) << grab.error;
  }
  EXPECT_LT(SecondsSince(start), 3.0);
  EXPECT_FALSE(MakeCameraCapture(CameraCaptureOptions{}, &error));
  EXPECT_FALSE(error.empty());
}

}  // namespace
}  // namespace igms::video
