// Regions, encodings and the overlay settings file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "common/wire/image_codec.h"
#include "tests/video_server/test_data.h"
#include "video_server/overlay_settings.h"

namespace igms::video {
namespace {

using wire::DecodeImage;
using wire::EncodeImage;
using wire::ImageEncoding;
using wire::ResolveRegion;

using testing::OpenCvData;

TEST(PixelRegion, WholeImageAndBoundsChecks) {
  const cv::Size size(640, 480);
  EXPECT_EQ(*ResolveRegion({}, size), cv::Rect(0, 0, 640, 480));
  EXPECT_EQ(*ResolveRegion({10, 20, 30, 40}, size), cv::Rect(10, 20, 30, 40));
  EXPECT_EQ(*ResolveRegion({0, 0, 640, 480}, size), cv::Rect(0, 0, 640, 480));
  const auto outside = ResolveRegion({600, 0, 41, 10}, size);
  EXPECT_FALSE(outside.ok());
  EXPECT_NE(outside.error().find("outside"), std::string::npos) << outside.error();
  EXPECT_NE(outside.error().find("640x480"), std::string::npos) << outside.error();
  EXPECT_FALSE(ResolveRegion({-1, 0, 10, 10}, size).ok());
  EXPECT_FALSE(ResolveRegion({5, 5, 0, 10}, size).ok());
  EXPECT_FALSE(ResolveRegion({1, 1, 2147483647, 10}, size).ok());
}

TEST(Codec, RawAndPngRoundTripARegionOfARealImage) {
  IGMS_REQUIRE_OPENCV_DATA();
  for (int flags : {cv::IMREAD_GRAYSCALE, cv::IMREAD_COLOR}) {
    const cv::Mat image = cv::imread(OpenCvData("aloeL.jpg"), flags);
    const cv::Mat region = image(cv::Rect(101, 33, 257, 190));
    for (ImageEncoding encoding : {ImageEncoding::kRaw, ImageEncoding::kPng}) {
      const std::string data = EncodeImage(region, encoding);
      const cv::Mat back = DecodeImage(data, encoding, 257, 190, image.channels());
      ASSERT_EQ(back.size(), region.size());
      ASSERT_EQ(back.type(), region.type());
      EXPECT_EQ(cv::norm(back, region, cv::NORM_INF), 0.0);
      if (encoding == ImageEncoding::kRaw) {
        EXPECT_EQ(data.size(), 257u * 190 * image.channels());
      }
    }
  }
  EXPECT_TRUE(DecodeImage("garbage", ImageEncoding::kPng, 0, 0, 0).empty());
  EXPECT_TRUE(DecodeImage("short", ImageEncoding::kRaw, 10, 10, 1).empty());
}

class OverlayFile : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = std::filesystem::temp_directory_path() /
              ("igms_overlay_" + std::to_string(::getpid()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(folder_);
    path_ = (folder_ / "overlay.yaml").string();
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }
  std::filesystem::path folder_;
  std::string path_;
};

TEST_F(OverlayFile, MissingFileGivesDefaultsAndSettingsSurviveARestart) {
  std::string error;
  auto initial = LoadOverlaySettings(path_);
  ASSERT_TRUE(initial.ok()) << initial.error();
  EXPECT_EQ(*initial, Overlay{});
  EXPECT_EQ(initial->key_level, 60);
  {
    OverlayStore store(path_, *initial);
    ASSERT_TRUE(store.Set({12, -7, 90}, &error)) << error;
    EXPECT_EQ(store.Get(), (Overlay{12, -7, 90}));
  }
  auto reloaded = LoadOverlaySettings(path_);
  ASSERT_TRUE(reloaded.ok()) << reloaded.error();
  EXPECT_EQ(*reloaded, (Overlay{12, -7, 90}));
}

TEST_F(OverlayFile, InvalidValuesAreRefusedAndChangeNothing) {
  OverlayStore store(path_, {});
  std::string error;
  ASSERT_TRUE(store.Set({1, 2, 3}, &error));
  EXPECT_FALSE(store.Set({1, 2, 300}, &error));
  EXPECT_NE(error.find("key level"), std::string::npos);
  EXPECT_FALSE(store.Set({99999, 2, 3}, &error));
  EXPECT_EQ(store.Get(), (Overlay{1, 2, 3}));
  EXPECT_EQ(*LoadOverlaySettings(path_), (Overlay{1, 2, 3}));
}

TEST_F(OverlayFile, CorruptFileIsAClearError) {
  std::ofstream(path_) << "u_offset_px: [not, a, number\n";
  const auto corrupt = LoadOverlaySettings(path_);
  EXPECT_FALSE(corrupt.ok());
  EXPECT_NE(corrupt.error().find(path_), std::string::npos) << corrupt.error();
  std::ofstream(path_) << "key_level: 1000\n";
  const auto out_of_range = LoadOverlaySettings(path_);
  EXPECT_FALSE(out_of_range.ok());
  EXPECT_NE(out_of_range.error().find("key level"), std::string::npos) << out_of_range.error();
}

TEST_F(OverlayFile, UnwritableFolderIsAnErrorAndKeepsTheOldSettings) {
  OverlayStore store((folder_ / "no" / "such" / "folder" / "overlay.yaml").string(), {});
  std::string error;
  EXPECT_FALSE(store.Set({5, 5, 5}, &error));
  EXPECT_FALSE(error.empty());
  EXPECT_EQ(store.Get(), Overlay{});
}

}  // namespace
}  // namespace igms::video
