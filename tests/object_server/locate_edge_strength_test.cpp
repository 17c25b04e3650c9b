// The bar an edge must clear inside the marks: set by the strongest edges there, or by a
// quantile of them so that a brighter object's few edges (a pipe's end on a block) do not
// raise it over the marked object's own; and the locator trying a refused block again with
// the quantile when its first fit left part of the marks empty, then with the gradient floor
// at the image's own noise; and a pipe whose outline explained the edges poorly tried again
// at that floor, the rival box held against it outright.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <variant>

#include "object_server/image_ops.h"
#include "object_server/locate.h"
#include "object_server/locate_steps.h"
#include "tests/object_server/site_request.h"

namespace igms::object {
namespace {

// A dim grey block (its foot on row 119) with a small white square on it, on a black
// background.
cv::Mat DimBlockUnderBrightSquare() {
  cv::Mat image(140, 160, CV_8U, cv::Scalar(10));
  cv::rectangle(image, cv::Rect(30, 30, 90, 90), cv::Scalar(60), cv::FILLED);
  cv::rectangle(image, cv::Rect(70, 40, 4, 4), cv::Scalar(250), cv::FILLED);
  return image;
}

std::vector<cv::Point2f> WholeImage(const cv::Mat& image) {
  return {{0, 0},
          {static_cast<float>(image.cols - 1), 0},
          {static_cast<float>(image.cols - 1), static_cast<float>(image.rows - 1)},
          {0, static_cast<float>(image.rows - 1)}};
}

// Whether one of `pixels` lies within 2 px of the block's foot.
bool OnTheBlocksFoot(const std::vector<cv::Point>& pixels) {
  for (const auto& p : pixels)
    if (p.x > 40 && p.x < 110 && std::abs(p.y - 119) <= 2) return true;
  return false;
}

TEST(EdgeStrength, TheLargestGradientSetsTheBarUnlessAQuantileIsAsked) {
  const cv::Mat image = DimBlockUnderBrightSquare();
  const Gradients grad(image, cv::Rect(0, 0, image.cols, image.rows), 1.0);
  double by_max = 0, by_quantile = 0;
  const auto strongest =
      StrongEdgePixels(grad, WholeImage(image), cv::Mat(), 0.35, 6.0, &by_max, 1.0);
  const auto quantile =
      StrongEdgePixels(grad, WholeImage(image), cv::Mat(), 0.35, 6.0, &by_quantile, 0.9);
  // The white square's step (190 grey levels) against the block's (50): by the largest, the
  // block's edges fall under 0.35 of the bar; by the 0.9 quantile (the block's outline holds
  // most edge pixels), they clear it.
  EXPECT_GT(by_max, 3 * by_quantile);
  EXPECT_FALSE(OnTheBlocksFoot(strongest));
  EXPECT_TRUE(OnTheBlocksFoot(quantile));
  EXPECT_GT(quantile.size(), strongest.size());
}

// A site scene's block (thesis cameras) found with the default options, its height within
// 0.1 in and its centre within 0.3 in; and with `without` (a retry turned off) refused, its
// fit leaving the marks' bottom empty.
void ExpectBlockFoundOnlyByTheRetry(uint64_t seed, site::SiteLevel level, const std::string& name,
                                    const LocateOptions& without) {
  const SiteRequest r = AskFor(seed, level, false, name);
  ASSERT_TRUE(r.present);
  const auto* truth = std::get_if<site::Box>(&r.shape);
  ASSERT_NE(truth, nullptr);
  const LocateResult found = Locate(r.input);
  ASSERT_TRUE(found.found) << found.detail;
  EXPECT_NEAR(found.box.size.z(), truth->size.z(), 0.1);
  EXPECT_LT((found.box.center - truth->center).norm(), 0.3);
  const LocateResult refused = Locate(r.input, without);
  EXPECT_FALSE(refused.found);
  EXPECT_EQ(refused.reason, Failure::kFitFailed);
  EXPECT_NE(refused.detail.find("empty on its bottom"), std::string::npos) << refused.detail;
}

TEST(EdgeStrength, ABlockUnderABrightPipesEndIsFoundOnTheSecondPass) {
  // Level pipes, thesis cameras, seed 35: support_9, in full view, a grey block with a white
  // pipe pointing at the cameras on its top. The pipe's end holds the strongest edges in the
  // marks; by them the block's sides are no edges, the boundary is the pipe's end alone, and
  // the fit leaves the marks' bottom empty. Tried again with the edges' 0.9 quantile as the
  // bar, the block is found.
  LocateOptions once;
  once.retry_edge_quantile = 0;
  once.retry_noise_gradient = 0;
  ExpectBlockFoundOnlyByTheRetry(35, site::SiteLevel::kPipes, "support_9", once);
}

TEST(EdgeStrength, TheNoiseIsMeasuredFromTheImageNotItsEdges) {
  // Grey 100 with Gaussian noise, and a bright square whose edges cross a tenth of the rows:
  // too few to move the median difference of neighbours.
  for (const double sigma : {2.0, 8.0}) {
    cv::Mat noise(200, 200, CV_32F);
    cv::RNG rng(7);
    rng.fill(noise, cv::RNG::NORMAL, 0, sigma);
    cv::Mat image(200, 200, CV_8U, cv::Scalar(100));
    cv::rectangle(image, cv::Rect(60, 60, 20, 20), cv::Scalar(220), cv::FILLED);
    cv::Mat noisy;
    image.convertTo(noisy, CV_32F);
    noisy += noise;
    noisy.convertTo(image, CV_8U);
    // Whole grey levels: the median difference is an integer, so the estimate steps by 1.05.
    EXPECT_NEAR(NoiseSigma(image, cv::Rect(0, 0, 200, 200)), sigma, 1.1) << sigma;
  }
  const cv::Mat flat(50, 50, CV_8U, cv::Scalar(40));
  EXPECT_EQ(NoiseSigma(flat, cv::Rect(0, 0, 50, 50)), 0.0);
  EXPECT_EQ(NoiseSigma(flat, cv::Rect(60, 60, 10, 10)), 0.0);  // outside the image
}

TEST(EdgeStrength, ABlocksFootInTheTablesShadeIsFoundWithTheFloorAtTheNoise) {
  // Level clutter, thesis cameras, seed 18: box_2, in full view, a grey block whose upper
  // part stands against the dark background and whose foot has about the table's shade.
  // The foot's step is under min_edge_gradient (set for the noisiest images), so the fit
  // stops at the table's far edge and leaves the marks' bottom empty, at the edges' 0.9
  // quantile too. With the floor at the image's noise, the foot is an edge and the block is
  // found.
  LocateOptions fixed_floor;
  fixed_floor.retry_noise_gradient = 0;
  ExpectBlockFoundOnlyByTheRetry(18, site::SiteLevel::kClutter, "box_2", fixed_floor);
}

TEST(EdgeStrength, AnUprightPipeInClutterIsFoundWithTheFloorAtTheNoise) {
  // Level clutter, thesis cameras, seed 23: upright_3, in full view 93 in away, a dark pipe
  // against the dark background above the table. At the fixed floor its outline explains the
  // edges poorly (score 0.93); tried again with the floor at the image's noise, the rival box
  // held against it outright, the pipe is found.
  const SiteRequest r = AskFor(23, site::SiteLevel::kClutter, false, "upright_3");
  ExpectPipeFound(r, {0.03, 0.1, 0.3});
  LocateOptions fixed_floor;
  fixed_floor.retry_noise_gradient = 0;
  ExpectRefused(r, fixed_floor, Failure::kLeftRightInconsistent);
}

TEST(EdgeStrength, ABlockAskedForAsAPipeAtTheNoiseFloorLosesToTheBoxOutright) {
  // Level clutter, thesis cameras, seed 18: box_4 asked for as a pipe. At the fixed floor the
  // pipe explains the edges poorly. At the image's noise the table's pattern lends it edges:
  // held against the box by other_type_ratio alone it is reported found, a pipe that is not
  // there; held against it outright, the box's better score refuses it.
  SiteRequest r = AskFor(18, site::SiteLevel::kClutter, false, "box_4");
  ASSERT_TRUE(r.present);
  r.input.type = SolidType::kCylinder;
  const LocateResult asked = Locate(r.input);
  EXPECT_FALSE(asked.found);
  EXPECT_EQ(asked.reason, Failure::kLeftRightInconsistent) << asked.detail;
  const auto pair = PrepareImages(r.input);
  ASSERT_TRUE(pair.ok());
  std::optional<LocateOptions> at_noise = NoiseFloorOptions(r.input, *pair, LocateOptions{});
  ASSERT_TRUE(at_noise.has_value());
  EXPECT_LT(at_noise->min_edge_gradient, LocateOptions{}.min_edge_gradient);
  at_noise->other_type_score = 0;
  EXPECT_TRUE(Locate(r.input, *at_noise).found);
  at_noise->other_type_outright = true;
  const LocateResult outright = Locate(r.input, *at_noise);
  EXPECT_FALSE(outright.found);
  EXPECT_NE(outright.detail.find("a box explains the outline better"), std::string::npos)
      << outright.detail;
}

TEST(EdgeStrength, ItsBoundsAreChecked) {
  std::string error;
  LocateOptions options;
  EXPECT_TRUE(options.Check(&error)) << error;
  // Options set out of bounds are refused, the message naming the option.
  const auto refused = [](const auto& set, const char* name) {
    LocateOptions o;
    set(o);
    std::string e;
    EXPECT_FALSE(o.Check(&e)) << name;
    EXPECT_NE(e.find(name), std::string::npos) << e;
  };
  for (const double q : {0.0, -0.5, 1.5})
    refused([q](LocateOptions& o) { o.edge_strength_quantile = q; }, "edge_strength_quantile");
  refused([](LocateOptions& o) { o.retry_edge_quantile = 1.2; }, "retry_edge_quantile");
  for (const double k : {-1.0, std::numeric_limits<double>::infinity()})
    refused([k](LocateOptions& o) { o.retry_noise_gradient = k; }, "retry_noise_gradient");
  refused([](LocateOptions& o) { o.retry_min_edge_gradient = 0; }, "retry_min_edge_gradient");
  // Both retries turned off.
  options.retry_edge_quantile = 0;
  options.retry_noise_gradient = 0;
  EXPECT_TRUE(options.Check(&error)) << error;
}

}  // namespace
}  // namespace igms::object
