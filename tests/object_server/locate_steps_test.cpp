// Steps 0-3 of the locator (object_server/locate_steps.h) on their own: on a rendered testbed
// scene with the operator's marks as modelled, and on small synthetic images where the right
// answer is known exactly. Failure modes are triggered on purpose. Steps 4-5 and the result:
// locate_fit_steps_test.cpp.
#include "object_server/locate_steps.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "object_server/solid_models.h"
#include "tests/object_server/locate_steps_fixture.h"
#include "tests/object_server/site_request.h"

namespace igms::object {
namespace {

using testing::Contains;
using testing::LocateSteps;

// --- 0. Images ---

TEST_F(LocateSteps, PrepareImagesTurnsColourToGreyAndKeepsGrey) {
  LocateInput in = Input(true);
  cv::Mat bgr;
  cv::cvtColor(images_->left, bgr, cv::COLOR_GRAY2BGR);
  in.left = bgr;
  const auto pair = PrepareImages(in);
  ASSERT_TRUE(pair.ok()) << pair.failure().detail;
  EXPECT_EQ(pair->left.type(), CV_8UC1);
  EXPECT_EQ(cv::norm(pair->left, images_->left, cv::NORM_INF), 0);
  EXPECT_EQ(cv::norm(pair->right, images_->right, cv::NORM_INF), 0);
  EXPECT_EQ(pair->left_camera, &in.left_camera);
  EXPECT_EQ(pair->right_camera, &in.right_camera);
}

TEST_F(LocateSteps, PrepareImagesRefusesMissingOddAndWrongSizedImages) {
  LocateInput in = Input(true);
  in.right = cv::Mat();
  auto r = PrepareImages(in);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.failure().reason, Failure::kBadInput);
  EXPECT_TRUE(Contains(r.failure().detail, "not empty")) << r.failure().detail;

  in = Input(true);
  in.left = cv::Mat(images_->left.size(), CV_16UC1, cv::Scalar(0));  // neither grey nor BGR
  r = PrepareImages(in);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.failure().reason, Failure::kBadInput);

  in = Input(true);
  in.right = cv::Mat(100, 100, CV_8U, cv::Scalar(0));
  r = PrepareImages(in);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.failure().reason, Failure::kBadInput);
  const auto size = scene_->cameras.left.image_size();
  EXPECT_TRUE(
      Contains(r.failure().detail, std::to_string(size.width) + "x" + std::to_string(size.height)))
      << r.failure().detail;
}

// --- 1. Marks ---

TEST_F(LocateSteps, MarkRegionIsTheMarksHullAtTheirMeanDepth) {
  const LocateInput in = Input(true);
  const auto region = MarkRegion(in);
  ASSERT_TRUE(region.ok()) << region.failure().detail;
  ASSERT_EQ(region->hull.size(), 4u);
  double depth = 0;
  for (const auto& m : in.marks) {
    depth += in.left_camera.Depth(m) / 4;
    const Eigen::Vector2d p = *in.left_camera.Project(m);
    bool found = false;
    for (const auto& h : region->hull)
      found |= std::abs(h.x - p.x()) < 1e-3 && std::abs(h.y - p.y()) < 1e-3;
    EXPECT_TRUE(found) << "mark at " << p.transpose() << " is not a hull corner";
  }
  EXPECT_NEAR(region->depth, depth, 1e-9);
  // The marks' region holds the cylinder's outline (the marks lie outside it, give or take
  // their jitter).
  const cv::Rect2d bounds = TrueBounds(*cylinder_);
  const cv::Point2f centre(static_cast<float>(bounds.x + 0.5 * bounds.width),
                           static_cast<float>(bounds.y + 0.5 * bounds.height));
  EXPECT_GT(cv::pointPolygonTest(region->hull, centre, true), 0.4 * bounds.width);
}

TEST_F(LocateSteps, MarkRegionFailuresNameTheirReason) {
  LocateInput in = Input(true);
  in.marks[2].z() = std::nan("");
  EXPECT_EQ(MarkRegion(in).failure().reason, Failure::kBadInput);

  in = Input(true);
  in.marks[1] = scene_->cameras.left.Center() + Eigen::Vector3d(0, 10, 0);  // behind: view is -y
  auto r = MarkRegion(in);
  EXPECT_EQ(r.failure().reason, Failure::kMarksBehindCamera);
  EXPECT_TRUE(Contains(r.failure().detail, "mark 2")) << r.failure().detail;

  in = Input(true);
  for (auto& m : in.marks) m = in.marks[0];
  r = MarkRegion(in);
  EXPECT_EQ(r.failure().reason, Failure::kMarksDegenerate);
  EXPECT_TRUE(Contains(r.failure().detail, "0.0 square pixels")) << r.failure().detail;

  in = Input(true);
  for (auto& m : in.marks) m.x() += 200;
  EXPECT_EQ(MarkRegion(in).failure().reason, Failure::kMarksOutsideImage);
}

// A mark in front of both cameras but so far to the side that its image lies at infinity:
// the projection has no point to give, and the marks are outside the image (this read an
// empty projection before).
TEST_F(LocateSteps, MarkWhoseImageIsAtInfinityIsOutsideTheImage) {
  LocateInput in = Input(true);
  // 50 in along the left camera's optical axis and 1e14 in square to it, to the side where
  // the right camera's depth grows too.
  auto optical_axis = [](const geometry::ProjectiveCamera& camera) {
    const Eigen::Vector3d m3 = camera.P().block<1, 3>(2, 0).transpose();
    return Eigen::Vector3d(m3.normalized() * (camera.P().leftCols<3>().determinant() < 0 ? -1 : 1));
  };
  const Eigen::Vector3d axis = optical_axis(in.left_camera);
  Eigen::Vector3d side = axis.cross(Eigen::Vector3d::UnitZ()).normalized();
  if (optical_axis(in.right_camera).dot(side) < 0) side = -side;
  in.marks[0] = in.left_camera.Center() + 50 * axis + 1e14 * side;
  ASSERT_GT(in.left_camera.Depth(in.marks[0]), 1e-6);
  ASSERT_GT(in.right_camera.Depth(in.marks[0]), 1e-6);
  ASSERT_FALSE(in.left_camera.Project(in.marks[0]).has_value());
  const auto r = MarkRegion(in);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.failure().reason, Failure::kMarksOutsideImage);
  EXPECT_TRUE(Contains(r.failure().detail, "mark 1 does not project")) << r.failure().detail;
}

// --- 2. Boundary ---

TEST_F(LocateSteps, KnownSolidsInFrontAreThoseNearerThanTheMarks) {
  LocateInput in = Input(true);
  const Eigen::Vector3d eye = scene_->cameras.left.Center();
  const Eigen::Vector3d to = (cylinder_->center - eye).normalized();
  const Eigen::Vector3d side = to.cross(Eigen::Vector3d::UnitZ()).normalized();
  auto block = [&](const std::string& name, double nearer) {
    KnownShape k{name, SolidType::kBox, Eigen::VectorXd(7)};
    k.params << cylinder_->center - nearer * to + 3 * side, 1, 1, 1, 0;
    return k;
  };
  KnownShape itself{"itself", SolidType::kCylinder, Eigen::VectorXd(7)};
  const Eigen::Vector3d half = 0.5 * cylinder_->height * cylinder_->axis;
  itself.params << cylinder_->center - half, cylinder_->center + half, cylinder_->radius;
  KnownShape broken = block("broken", 10);
  broken.params[3] = std::numeric_limits<double>::quiet_NaN();
  in.known = {block("behind", -10), itself, block("in front", 10), broken};
  const auto marks = MarkRegion(in);
  ASSERT_TRUE(marks.ok());
  const auto in_front = KnownSolidsInFront(in, *marks, options_);
  ASSERT_EQ(in_front.size(), 1u);
  EXPECT_EQ(in_front[0].name, "in front");
  // Its silhouette in each view, grown by hidden_grow_px: its centre inside, the object's
  // centre not.
  const Eigen::Vector3d centre = cylinder_->center - 10 * to + 3 * side;
  for (int v = 0; v < 2; ++v) {
    const auto& camera = v == 0 ? scene_->cameras.left : scene_->cameras.right;
    EXPECT_TRUE(InsideAny({in_front[0].outline[v]}, *camera.Project(centre)));
    EXPECT_FALSE(InsideAny({in_front[0].outline[v]}, *camera.Project(cylinder_->center)));
  }
  // The boundary's candidates leave its pixels out; without a solid in front, no mask.
  const cv::Mat mask = VisibleEdgeMask(in_front, cv::Mat(), in.left.size());
  const Eigen::Vector2d c = *scene_->cameras.left.Project(centre);
  const Eigen::Vector2d o = *scene_->cameras.left.Project(cylinder_->center);
  EXPECT_EQ(mask.at<uint8_t>(cvRound(c.y()), cvRound(c.x())), 0);
  EXPECT_EQ(mask.at<uint8_t>(cvRound(o.y()), cvRound(o.x())), 255);
  EXPECT_TRUE(VisibleEdgeMask({}, cv::Mat(), in.left.size()).empty());
}

// A known slab 6 in in front of the marks' right part (seen beside the pipe's side): a
// refusal names it.
TEST_F(LocateSteps, ARefusalNamesTheKnownSolidsInFrontOfTheMarks) {
  LocateInput in = Input(true);
  const Eigen::Vector3d eye = scene_->cameras.left.Center();
  const Eigen::Vector3d to = (cylinder_->center - eye).normalized();
  const Eigen::Vector3d side = to.cross(Eigen::Vector3d::UnitZ()).normalized();
  const double depth = (cylinder_->center - eye).dot(to), nearer = (depth - 6) / depth;
  // Seen where a point 0.5 in beyond the pipe's side is, 1 in wide there.
  KnownShape slab{"slab", SolidType::kBox, Eigen::VectorXd(7)};
  slab.params << cylinder_->center - 6 * to + (cylinder_->radius + 0.5) * nearer * side, nearer,
      0.3, 2 * cylinder_->height, std::atan2(side.y(), side.x());
  in.known = {slab};
  in.right = cv::Mat(in.right.size(), in.right.type(), cv::Scalar(90));  // nothing to match
  const LocateResult r = Locate(in);
  EXPECT_FALSE(r.found);
  EXPECT_TRUE(Contains(r.detail, "(in front of part of the marks: slab)")) << r.detail;
  in.known.clear();
  EXPECT_FALSE(Contains(Locate(in).detail, "in front of"));
}

TEST(LocateStepsGeometry, GrowPolygonMovesEveryVertexAwayFromTheCentre) {
  const std::vector<cv::Point2f> square = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  const auto grown = GrowPolygon(square, std::sqrt(2.0));
  ASSERT_EQ(grown.size(), 4u);
  EXPECT_NEAR(grown[0].x, -1, 1e-5);
  EXPECT_NEAR(grown[0].y, -1, 1e-5);
  EXPECT_NEAR(grown[2].x, 11, 1e-5);
  EXPECT_NEAR(grown[2].y, 11, 1e-5);
  // A polygon shrunk to a point has no direction to grow in.
  const std::vector<cv::Point2f> point(3, cv::Point2f(5, 5));
  EXPECT_EQ(GrowPolygon(point, 4), point);
}

TEST(LocateStepsGeometry, GrowRectStaysInsideTheImage) {
  const cv::Rect image(0, 0, 100, 80);
  EXPECT_EQ(GrowRect(cv::Rect(10, 10, 20, 20), 5, image), cv::Rect(5, 5, 30, 30));
  EXPECT_EQ(GrowRect(cv::Rect(2, 70, 20, 20), 5, image), cv::Rect(0, 65, 27, 15));
  LocateOptions options;
  options.search_px = 6;
  options.boundary_grow_px = 4;
  EXPECT_EQ(RegionPad(options), 14);
}

TEST(LocateStepsGeometry, LargestConnectedKeepsTheBiggestSetAcrossOnePixelGaps) {
  std::vector<cv::Point> pixels;
  for (int x = 0; x <= 16; x += 2) pixels.emplace_back(x, 5);  // 9 pixels, one-pixel gaps
  for (int x = 40; x < 45; ++x) pixels.emplace_back(x, 5);     // 5 touching pixels
  const auto largest = LargestConnected(pixels);
  ASSERT_EQ(largest.size(), 9u);
  for (const auto& p : largest) EXPECT_LE(p.x, 16);
  // Each pixel is grown by one, so gaps of two are bridged too, but not gaps of three.
  const std::vector<cv::Point> two = {{0, 0}, {3, 0}, {6, 0}};
  EXPECT_EQ(LargestConnected(two).size(), 3u);
  const std::vector<cv::Point> three = {{0, 0}, {4, 0}, {8, 0}};
  EXPECT_EQ(LargestConnected(three).size(), 1u);
  EXPECT_TRUE(LargestConnected({}).empty());
}

// A dark disc on a light background with a small bright blob inside the marks' margin: the
// boundary is the disc's outline alone.
TEST(LocateStepsGeometry, FindBoundaryIsTheObjectsOutlineNotANeighboursEdge) {
  cv::Mat image(120, 160, CV_8U, cv::Scalar(180));
  cv::circle(image, {70, 60}, 25, cv::Scalar(60), cv::FILLED, cv::LINE_AA);
  cv::rectangle(image, cv::Rect(100, 20, 3, 3), cv::Scalar(255), cv::FILLED);
  MarkedRegion marks;
  marks.hull = {{40, 28}, {104, 28}, {104, 92}, {40, 92}};
  marks.depth = 50;
  LocateOptions options;
  const Gradients grad(image, cv::Rect(20, 10, 110, 100), options.edge_sigma);
  const Boundary b = FindBoundary(grad, marks, cv::Mat(), options);
  ASSERT_FALSE(b.pixels.empty());
  EXPECT_GT(b.strongest, 30);
  for (const auto& p : b.pixels) {
    const double r = std::hypot(p.x - 70, p.y - 60);
    EXPECT_NEAR(r, 25, 2.5) << p;
  }
  EXPECT_FALSE(CheckBoundary(b, marks, options).has_value());
  // The grown region is the marks' hull grown by boundary_grow_px.
  EXPECT_NEAR(b.region[0].x, 40 - options.boundary_grow_px / std::sqrt(2.0), 1e-4);

  // An edge map with no edges leaves nothing: no edge near the marks.
  const Boundary none = FindBoundary(grad, marks, cv::Mat::zeros(image.size(), CV_8U), options);
  EXPECT_TRUE(none.pixels.empty());
  const auto failure = CheckBoundary(none, marks, options);
  ASSERT_TRUE(failure.has_value());
  EXPECT_EQ(failure->reason, Failure::kNoEdgeNearMarks);
  EXPECT_TRUE(Contains(failure->detail, "strongest")) << failure->detail;

  // The edge map restricts the boundary to its pixels: the disc's right half only.
  cv::Mat right_half = cv::Mat::zeros(image.size(), CV_8U);
  right_half(cv::Rect(71, 0, 89, 120)).setTo(255);
  const Boundary half = FindBoundary(grad, marks, right_half, options);
  ASSERT_FALSE(half.pixels.empty());
  for (const auto& p : half.pixels) EXPECT_GT(p.x, 70);
}

TEST(LocateStepsGeometry, CheckBoundaryWantsEnoughPixelsForTheMarksPerimeter) {
  MarkedRegion marks;
  marks.hull = {{0, 0}, {100, 0}, {100, 100}, {0, 100}};  // perimeter 400
  LocateOptions options;
  options.min_boundary_share = 0.25;
  Boundary b;
  b.pixels.assign(99, cv::Point(1, 1));
  const auto failure = CheckBoundary(b, marks, options);
  ASSERT_TRUE(failure.has_value());
  EXPECT_EQ(failure->reason, Failure::kEdgeCountMismatch);
  EXPECT_TRUE(Contains(failure->detail, "99 boundary pixels")) << failure->detail;
  b.pixels.assign(100, cv::Point(1, 1));
  EXPECT_FALSE(CheckBoundary(b, marks, options).has_value());
}

TEST_F(LocateSteps, BoundaryOfTheRenderedCylinderLiesOnItsOutline) {
  const LocateInput in = Input(true);
  const Through3 t = RunThroughStep3(in);
  EXPECT_FALSE(CheckBoundary(t.boundary, t.marks, options_).has_value());
  const cv::Rect2d bounds = TrueBounds(*cylinder_);
  const cv::Rect found = cv::boundingRect(t.boundary.pixels);
  // Strong edge pixels straddle the outline by a pixel or two.
  EXPECT_NEAR(found.x, bounds.x, 3.0);
  EXPECT_NEAR(found.y, bounds.y, 3.0);
  EXPECT_NEAR(found.x + found.width - 1, bounds.x + bounds.width, 3.0);
  EXPECT_NEAR(found.y + found.height - 1, bounds.y + bounds.height, 3.0);
  for (const auto& p : t.boundary.pixels)
    EXPECT_GE(cv::pointPolygonTest(t.boundary.region, cv::Point2f(p.x, p.y), false), 0) << p;
}

// --- 3. Depth ---

TEST(LocateStepsGeometry, DepthSearchIsTheMarksDepthWithinTheTolerance) {
  const std::vector<cv::Point> boundary = {{10, 20}, {30, 20}, {30, 60}, {10, 60}};
  LocateOptions options;
  options.depth_tolerance = 3;
  DepthSearch s = ObjectDepthSearch(boundary, 50, options);
  EXPECT_DOUBLE_EQ(s.near, 47);
  EXPECT_DOUBLE_EQ(s.far, 53);
  EXPECT_EQ(s.patch, cv::Rect(7, 17, 27, 47));
  EXPECT_DOUBLE_EQ(s.centre.x(), 20);
  EXPECT_DOUBLE_EQ(s.centre.y(), 40);
  // Never nearer than half the marks' depth.
  s = ObjectDepthSearch(boundary, 4, options);
  EXPECT_DOUBLE_EQ(s.near, 2);
  EXPECT_DOUBLE_EQ(s.far, 7);
}

TEST(LocateStepsGeometry, AMatchOnTheObjectsBandFollowsItsEdgesNotWhatLiesBesideIt) {
  // The object: a bar 4 px wide, 10 px further left in the right image. Beside it and farther
  // off, a textured block filling most of the patch, 4 px further left.
  cv::Mat left(80, 140, CV_8U, cv::Scalar(20));
  cv::Mat right = left.clone();
  cv::Mat texture(50, 40, CV_8U);
  cv::RNG rng(7);
  rng.fill(texture, cv::RNG::UNIFORM, 0, 256);
  left(cv::Rect(40, 15, 4, 50)).setTo(200);
  right(cv::Rect(30, 15, 4, 50)).setTo(200);
  texture.copyTo(left(cv::Rect(48, 15, 40, 50)));
  texture.copyTo(right(cv::Rect(44, 15, 40, 50)));
  const cv::Rect patch(36, 12, 56, 56);
  const Eigen::Vector2d a(-14, 0), b(-2, 0);
  const SsdMatch whole = MatchAlongSegment(left, right, patch, a, b);
  ASSERT_TRUE(whole.ok);
  EXPECT_NEAR(whole.offset.x(), -4, 0.5);  // the block's
  // The bar's edges and 3 px either side.
  cv::Mat band = cv::Mat::zeros(patch.size(), CV_8U);
  band(cv::Rect(40 - patch.x - 3, 0, 4 + 6, patch.height)).setTo(255);
  const SsdMatch banded = MatchAlongSegment(left, right, patch, a, b, band);
  ASSERT_TRUE(banded.ok);
  EXPECT_NEAR(banded.offset.x(), -10, 0.5);
  EXPECT_GT(banded.zncc, 0.9);
  EXPECT_LT(banded.rms, 1.0);
  // A mask not of the patch's size matches nothing.
  EXPECT_FALSE(MatchAlongSegment(left, right, patch, a, b, cv::Mat::zeros(5, 5, CV_8U)).ok);
}

TEST_F(LocateSteps, TheMatchTriangulatesToTheCylindersFrontDepth) {
  const LocateInput in = Input(true);
  const Through3 t = RunThroughStep3(in);
  EXPECT_FALSE(CheckMatch(t.match, options_).has_value());
  EXPECT_GT(t.match.zncc, options_.min_match_zncc);
  const double front = site::FrontDepth(*cylinder_, in.left_camera);
  EXPECT_NEAR(t.depth, front, 1.5);  // a pixel of disparity is about 1 in here
  // The right image's region is the patch moved by the match and grown.
  const cv::Rect image(0, 0, t.pair.right.cols, t.pair.right.rows);
  const cv::Rect right = RightRegion(t.search, t.match, 5, image);
  EXPECT_EQ(right.x, std::max(0, t.search.patch.x + int(std::round(t.match.offset.x())) - 5));
  EXPECT_EQ(right.height, std::min(image.height, t.search.patch.height + 10));
}

TEST_F(LocateSteps, MatchObjectFailsWhenTheSearchLeavesTheRightImage) {
  const LocateInput in = Input(true);
  Through3 t = RunThroughStep3(in);
  // So near that the disparity carries the patch out of the right image.
  t.search.near = 0.5;
  t.search.far = 1.0;
  const auto r = MatchObject(t.pair, t.search, options_);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.failure().reason, Failure::kMatchOverThreshold);
  EXPECT_TRUE(Contains(r.failure().detail, "leaves the right image")) << r.failure().detail;
}

TEST_F(LocateSteps, APatchReachingPastTheRightImageAtEveryDepthIsMatchedOnWhatStaysIn) {
  const LocateInput in = Input(true);
  Through3 t = RunThroughStep3(in);
  ASSERT_LT(t.match.offset.x(), -1);  // the right image sees the cylinder further left
  // The patch taken out to the left image's edge (marks taking in what lies beside the
  // object): shifted by any disparity of the search, it leaves the right image.
  DepthSearch wide = t.search;
  wide.patch.width += wide.patch.x;
  wide.patch.x = 0;
  const auto r = MatchObject(t.pair, wide, options_);
  ASSERT_TRUE(r.ok()) << r.failure().detail;
  EXPECT_FALSE(CheckMatch(*r, options_).has_value());
  // The table beside the cylinder, at other depths, weighs in: within the depth the fit's
  // starts reach (about a pixel of disparity per inch here).
  EXPECT_NEAR(r->offset.x(), t.match.offset.x(), 2.5);
  EXPECT_NEAR(r->offset.y(), t.match.offset.y(), 0.5);
  // Kept in, the whole patch is matched as before.
  const auto again = MatchObject(t.pair, t.search, options_);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->offset, t.match.offset);
}

TEST(LocateStepsSite, APipeNearTheRightImagesEdgeIsMatchedAndFound) {
  // Level clutter, seed 10, the thesis's cameras: upright_11 stands 13 px from the right
  // image's left edge, and its boundary takes in edges 20 px beside it; at no depth of the
  // search did the whole patch stay in the right image.
  // Nothing holds its length well (a sigma of 1.4 in): it is 0.5 in short, within that.
  const SiteRequest r = AskFor(10, site::SiteLevel::kClutter, false, "upright_11");
  const LocateResult found = ExpectPipeFound(r, {.length = 4.0, .centre = 0.3});
  const auto* truth = std::get_if<site::Cylinder>(&r.shape);
  ASSERT_TRUE(found.found && truth);
  EXPECT_LT(std::abs(found.cylinder.height - truth->height), 2 * found.cylinder.height_sigma);
}

TEST(LocateStepsGeometry, CheckMatchHoldsTheCorrelationLimit) {
  LocateOptions options;
  options.min_match_zncc = 0.5;
  SsdMatch m;
  m.ok = true;
  m.rms = 60;  // a large SSD alone refuses nothing: a dark or noisy pair has one
  m.zncc = 0.5;
  EXPECT_FALSE(CheckMatch(m, options).has_value());
  m.zncc = 0.45;
  const auto failure = CheckMatch(m, options);
  ASSERT_TRUE(failure.has_value());
  EXPECT_EQ(failure->reason, Failure::kMatchOverThreshold);
  EXPECT_TRUE(Contains(failure->detail, "correlates 0.45")) << failure->detail;
}

TEST_F(LocateSteps, ARangeThatAgreesNarrowsTheMatchAndOneThatDoesNotIsOnlyRecorded) {
  LocateInput in = Input(true);
  const Through3 t = RunThroughStep3(in);
  // No range: the match as it was, the check unused.
  RangeCheck check;
  SsdMatch m =
      NarrowByRange(in, t.pair, t.search, t.boundary, t.marks.depth, t.match, options_, &check);
  EXPECT_FALSE(check.used);
  EXPECT_EQ(m.offset, t.match.offset);

  // A ranger above the left camera aimed at the cylinder's axis, reading its front surface.
  in.ranger_origin = in.left_camera.Center() + Eigen::Vector3d(0, 0, 6);
  in.ranger_axis = (cylinder_->center - in.ranger_origin).normalized();
  const double range = (cylinder_->center - in.ranger_origin).norm() - cylinder_->radius;
  in.range = range;
  check = RangeCheck{};
  m = NarrowByRange(in, t.pair, t.search, t.boundary, t.marks.depth, t.match, options_, &check);
  EXPECT_TRUE(check.used);
  EXPECT_DOUBLE_EQ(check.measured, range);
  EXPECT_TRUE(check.constrained);
  const auto x = TriangulateMatch(t.pair, t.search, m);
  ASSERT_TRUE(x.has_value());
  EXPECT_NEAR(in.left_camera.Depth(*x), site::FrontDepth(*cylinder_, in.left_camera), 1.5);

  // 20 in beyond: far from the marks' depth, so it does not narrow the search.
  in.range = range + 20;
  check = RangeCheck{};
  m = NarrowByRange(in, t.pair, t.search, t.boundary, t.marks.depth, t.match, options_, &check);
  EXPECT_TRUE(check.used);
  EXPECT_FALSE(check.constrained);
  EXPECT_EQ(m.offset, t.match.offset);
}

}  // namespace
}  // namespace igms::object
