// Edge detection on real images, against a bare cv::Canny and against known geometry.
#include "video_server/edges.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tests/video_server/test_data.h"

namespace igms::video {
namespace {

using testing::OpenCvData;

TEST(Edges, DefaultSigmaIsTheNarrowReadingOfTheThesis) {
  EXPECT_NEAR(kDefaultEdgeSigma, 1.0607, 1e-4);
  EXPECT_EQ(EdgeOptions{}.sigma, kDefaultEdgeSigma);
  std::string error;
  EXPECT_TRUE(EdgeOptions{}.Check(&error)) << error;
}

TEST(Edges, OptionsAreValidated) {
  std::string error;
  EdgeOptions options;
  options.sigma = -1;
  EXPECT_FALSE(options.Check(&error));
  options = {};
  options.low_threshold = 200;
  options.high_threshold = 100;
  EXPECT_FALSE(options.Check(&error));
  options = {};
  options.high_threshold = std::nan("");
  EXPECT_FALSE(options.Check(&error));
  EXPECT_THROW(DetectEdges(cv::Mat(10, 10, CV_8UC1), options), std::invalid_argument);
}

// The same smoothing followed by OpenCV's own Canny gives the same edge map: the detector
// is Canny, not an approximation of it.
TEST(Edges, MatchesBareOpenCvCannyOnRealImages) {
  IGMS_REQUIRE_OPENCV_DATA();
  for (const char* name : {"left01.jpg", "aloeL.jpg"}) {
    const cv::Mat image = cv::imread(OpenCvData(name), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(image.empty());
    const cv::Mat original = image.clone();
    const EdgeOptions options;
    const EdgeImage edges = DetectEdges(image, options);
    EXPECT_EQ(cv::norm(image, original, cv::NORM_INF), 0.0) << "the input was modified";
    cv::Mat smooth, expected;
    cv::GaussianBlur(image, smooth, cv::Size(0, 0), options.sigma, options.sigma,
                     cv::BORDER_REPLICATE);
    cv::Canny(smooth, expected, options.low_threshold, options.high_threshold, 3, true);
    ASSERT_EQ(edges.edges.size(), image.size());
    const int total = cv::countNonZero(expected);
    const int differing = cv::countNonZero(edges.edges != expected);
    EXPECT_GT(total, 1000) << name;
    EXPECT_LE(differing, total / 1000) << name << ": " << differing << " of " << total;
    EXPECT_EQ(edges.edge_count(), cv::countNonZero(edges.edges));
    EXPECT_EQ(static_cast<int>(edges.row_start.size()), image.rows + 1);
    EXPECT_EQ(edges.row_start.back(), edges.edge_count());
  }
}

TEST(Edges, ColourImagesAreDetectedAsGrey) {
  IGMS_REQUIRE_OPENCV_DATA();
  const cv::Mat colour = cv::imread(OpenCvData("aloeL.jpg"));
  cv::Mat grey;
  cv::cvtColor(colour, grey, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(cv::countNonZero(DetectEdges(colour, {}).edges != DetectEdges(grey, {}).edges), 0);
}

// A bright disc on a dark ground: its edge is a circle of the disc's radius, and the
// gradient at every edge pixel points inwards, from dark to bright.
TEST(Edges, DirectionPointsFromDarkToBrightAcrossADisc) {
  const cv::Point2d centre(160.3, 120.6);
  const double radius = 60.0;
  cv::Mat image(240, 320, CV_8UC1, cv::Scalar(20));
  cv::circle(image, cv::Point(cvRound(centre.x * 16), cvRound(centre.y * 16)), cvRound(radius * 16),
             cv::Scalar(220), cv::FILLED, cv::LINE_AA, 4);
  const EdgeImage edges = DetectEdges(image, {});
  ASSERT_GT(edges.edge_count(), 300);
  int index = 0;
  double worst_angle = 0.0, worst_radius = 0.0;
  for (int v = 0; v < image.rows; ++v) {
    for (int u = 0; u < image.cols; ++u) {
      if (!edges.edges.at<uint8_t>(v, u)) continue;
      const double inward = std::atan2(centre.y - v, centre.x - u);
      double difference = std::abs(edges.direction_rad[index++] - inward);
      difference = std::min(difference, 2 * std::numbers::pi - difference);
      worst_angle = std::max(worst_angle, difference);
      worst_radius =
          std::max(worst_radius, std::abs(std::hypot(u - centre.x, v - centre.y) - radius));
    }
  }
  EXPECT_LT(worst_angle, 0.15);
  EXPECT_LT(worst_radius, 1.5);
}

// Each direction is atan2 of the Sobel derivatives of the smoothed image at that pixel.
TEST(Edges, DirectionsAreAtan2OfTheSmoothedGradient) {
  IGMS_REQUIRE_OPENCV_DATA();
  const cv::Mat image = cv::imread(OpenCvData("aloeL.jpg"), cv::IMREAD_GRAYSCALE);
  const EdgeOptions options;
  const EdgeImage edges = DetectEdges(image, options);
  cv::Mat smooth, du, dv;
  cv::GaussianBlur(image, smooth, cv::Size(0, 0), options.sigma, options.sigma,
                   cv::BORDER_REPLICATE);
  cv::Sobel(smooth, du, CV_32F, 1, 0, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
  cv::Sobel(smooth, dv, CV_32F, 0, 1, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
  int index = 0;
  double worst = 0.0;
  for (int v = 0; v < image.rows; ++v) {
    for (int u = 0; u < image.cols; ++u) {
      if (!edges.edges.at<uint8_t>(v, u)) continue;
      const double exact = std::atan2(dv.at<float>(v, u), du.at<float>(v, u));
      double difference = std::abs(edges.direction_rad[index++] - exact);
      worst = std::max(worst, std::min(difference, 2 * std::numbers::pi - difference));
    }
  }
  EXPECT_EQ(index, edges.edge_count());
  EXPECT_LT(worst, 2e-5);
}

TEST(Edges, RegionDirectionsAreTheFullListRestrictedToTheRegion) {
  IGMS_REQUIRE_OPENCV_DATA();
  const EdgeImage edges =
      DetectEdges(cv::imread(OpenCvData("left01.jpg"), cv::IMREAD_GRAYSCALE), {});
  const cv::Rect region(100, 50, 200, 150);
  std::vector<float> expected;
  int index = 0;
  for (int v = 0; v < edges.edges.rows; ++v) {
    for (int u = 0; u < edges.edges.cols; ++u) {
      if (!edges.edges.at<uint8_t>(v, u)) continue;
      if (region.contains(cv::Point(u, v))) expected.push_back(edges.direction_rad[index]);
      ++index;
    }
  }
  EXPECT_GT(expected.size(), 100u);
  EXPECT_EQ(DirectionsInRegion(edges, region), expected);
  EXPECT_EQ(DirectionsInRegion(edges, cv::Rect(0, 0, 640, 480)), edges.direction_rad);
}

TEST(Edges, EmptyImageGivesNoEdges) {
  const EdgeImage edges = DetectEdges(cv::Mat(), {});
  EXPECT_TRUE(edges.edges.empty());
  EXPECT_EQ(edges.edge_count(), 0);
}

}  // namespace
}  // namespace igms::video
