// Each step of the locator (object_server/locate_steps.h) on its own: on a rendered testbed
// scene with the operator's marks as modelled, and on small synthetic images and solids where
// the right answer is known exactly. Failure modes are triggered on purpose.
#include "object_server/locate_steps.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "common/sim/marks.h"
#include "common/sim/renderer.h"
#include "common/sim/testbed.h"
#include "object_server/solid_models.h"

namespace igms::object {
namespace {

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A rendered scene with its first upright cylinder and its first box marked.
class LocateSteps : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new site::Scene(site::RandomTestbedScene(42));
    images_ = new site::StereoImages(site::RenderStereo(*scene_));
  }
  static void TearDownTestSuite() {
    delete images_;
    delete scene_;
  }
  void SetUp() override {
    for (size_t i = 0; i < scene_->objects.size(); ++i) {
      const auto& shape = scene_->objects[i].shape;
      if (const auto* c = std::get_if<site::Cylinder>(&shape); c && !cylinder_ && c->axis.z() > 0.9)
        cylinder_ = c;
      if (const auto* b = std::get_if<site::Box>(&shape); b && !box_) box_ = b;
    }
    ASSERT_NE(cylinder_, nullptr);
    ASSERT_NE(box_, nullptr);
  }
  LocateInput Input(bool cylinder) const {
    LocateInput in;
    in.type = cylinder ? SolidType::kCylinder : SolidType::kBox;
    const site::Shape shape = cylinder ? site::Shape(*cylinder_) : site::Shape(*box_);
    in.marks = *site::GenerateMarks(shape, scene_->cameras.left, 7);
    in.left = images_->left;
    in.right = images_->right;
    in.left_camera = scene_->cameras.left;
    in.right_camera = scene_->cameras.right;
    return in;
  }
  // The object's bounding rectangle in the left image.
  cv::Rect2d TrueBounds(const site::Shape& shape) const {
    double u0, v0, u1, v1;
    EXPECT_TRUE(site::ImageBounds(shape, scene_->cameras.left, u0, v0, u1, v1));
    return cv::Rect2d(u0, v0, u1 - u0, v1 - v0);
  }
  // Steps 0-3 of a good input, as Locate runs them.
  struct Through3 {
    StereoPair pair;
    MarkedRegion marks;
    Boundary boundary;
    DepthSearch search;
    SsdMatch match;
    double depth = 0;
  };
  Through3 RunThroughStep3(const LocateInput& in, const Gradients** grad_left = nullptr) {
    Through3 t;
    const auto pair = PrepareImages(in);
    EXPECT_TRUE(pair.ok()) << pair.failure().detail;
    t.pair = *pair;
    const auto marks = MarkRegion(in);
    EXPECT_TRUE(marks.ok()) << marks.failure().detail;
    t.marks = *marks;
    const cv::Rect image(0, 0, t.pair.left.cols, t.pair.left.rows);
    left_gradients_ =
        Gradients(t.pair.left, GrowRect(cv::boundingRect(t.marks.hull), RegionPad(options_), image),
                  options_.edge_sigma);
    if (grad_left) *grad_left = &left_gradients_;
    t.boundary = FindBoundary(left_gradients_, t.marks, cv::Mat(), options_);
    t.search = ObjectDepthSearch(t.boundary.pixels, t.marks.depth, options_);
    const auto match = MatchObject(t.pair, t.search, options_);
    EXPECT_TRUE(match.ok()) << match.failure().detail;
    t.match = *match;
    const auto x = TriangulateMatch(t.pair, t.search, t.match);
    EXPECT_TRUE(x.has_value());
    t.depth = x ? in.left_camera.Depth(*x) : 0;
    return t;
  }

  static site::Scene* scene_;
  static site::StereoImages* images_;
  const site::Cylinder* cylinder_ = nullptr;
  const site::Box* box_ = nullptr;
  LocateOptions options_;
  Gradients left_gradients_;
};
site::Scene* LocateSteps::scene_ = nullptr;
site::StereoImages* LocateSteps::images_ = nullptr;

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

// --- 4. Starting models and the fit ---

TEST_F(LocateSteps, AnUprightCylinderStartsNearItsTruthAndFitsOntoIt) {
  const LocateInput in = Input(true);
  const Through3 t = RunThroughStep3(in);
  const auto starts = CylinderStarts(t.pair, t.boundary.pixels, t.depth, t.search, options_);
  ASSERT_GE(starts.size(), 1u);
  ASSERT_LE(starts.size(), 2u);
  const Eigen::VectorXd& x0 = starts[0];
  // A second start only when the ends' own matches put them further apart in depth than the
  // radius.
  if (starts.size() == 2) {
    EXPECT_GT(std::abs(in.left_camera.Depth(starts[1].segment<3>(0)) -
                       in.left_camera.Depth(starts[1].segment<3>(3))),
              x0[6]);
  }
  ASSERT_EQ(x0.size(), 7);
  EXPECT_NEAR(x0[6], cylinder_->radius, 0.3 * cylinder_->radius);
  const Eigen::Vector3d axis = (x0.segment<3>(3) - x0.segment<3>(0)).normalized();
  EXPECT_GT(std::abs(axis.z()), 0.99);
  EXPECT_LT((0.5 * (x0.segment<3>(0) + x0.segment<3>(3)) - cylinder_->center).norm(), 2.0);

  const cv::Rect image(0, 0, t.pair.right.cols, t.pair.right.rows);
  const Gradients grad_right(t.pair.right,
                             RightRegion(t.search, t.match, RegionPad(options_), image),
                             options_.edge_sigma);
  const std::array<FitView, 2> views = {FitView{&in.left_camera, &left_gradients_},
                                        FitView{&in.right_camera, &grad_right}};
  const FitOutcome f =
      FitCylinder(starts, views, FitSettings(options_, t.boundary.strongest), options_);
  ASSERT_TRUE(f.ok) << f.error;
  EXPECT_FALSE(CheckBothViews(f, options_).has_value());
  const CylinderResult c = CylinderFromFit(f.params, f.covariance);
  EXPECT_NEAR(c.radius, cylinder_->radius, 0.05);
  EXPECT_NEAR(c.height, cylinder_->height, 0.2);
  EXPECT_LT((c.center - cylinder_->center).norm(), 0.5);
  EXPECT_GT(c.axis.dot(cylinder_->axis), 0.999);
}

TEST_F(LocateSteps, ABoxStartsWorldAlignedAtThreeDepthsAndFitsOntoIt) {
  const LocateInput in = Input(false);
  const Through3 t = RunThroughStep3(in);
  const auto starts = BoxStarts(in.left_camera, t.boundary.pixels, t.depth);
  ASSERT_EQ(starts.size(), 3u);
  for (const auto& s : starts) {
    ASSERT_EQ(s.size(), 7);
    EXPECT_EQ(s[6], 0.0);
    // The same extent across the view (x, z: the cameras look along -y) from one front plane.
    EXPECT_DOUBLE_EQ(s[3], starts[0][3]);
    EXPECT_DOUBLE_EQ(s[5], starts[0][5]);
    // ... and one front face: the box's near end along y is where the first start's is.
    const double near_end = std::abs(s[1] + 0.5 * s[4] - (starts[0][1] + 0.5 * starts[0][4])) < 1e-9
                                ? 0
                                : std::abs(s[1] - 0.5 * s[4] - (starts[0][1] - 0.5 * starts[0][4]));
    EXPECT_LT(near_end, 1e-9);
  }
  // Along the view: the mean of the two across, then 0.4 and 1.8 times that.
  const double across = 0.5 * (starts[0][3] + starts[0][5]);
  EXPECT_NEAR(starts[0][4], across, 1e-9);
  EXPECT_NEAR(starts[1][4], 0.4 * across, 1e-9);
  EXPECT_NEAR(starts[2][4], 1.8 * across, 1e-9);

  const cv::Rect image(0, 0, t.pair.right.cols, t.pair.right.rows);
  const Gradients grad_right(t.pair.right,
                             RightRegion(t.search, t.match, RegionPad(options_), image),
                             options_.edge_sigma);
  const std::array<FitView, 2> views = {FitView{&in.left_camera, &left_gradients_},
                                        FitView{&in.right_camera, &grad_right}};
  const FitOutcome f = FitBox(starts, views, FitSettings(options_, t.boundary.strongest), options_);
  ASSERT_TRUE(f.ok) << f.error;
  ASSERT_EQ(f.params.size(), 7);
  EXPECT_EQ(f.covariance.rows(), 7);
  EXPECT_FALSE(CheckBothViews(f, options_).has_value());
  const BoxResult b = BoxFromFit(f.params, f.covariance);
  EXPECT_LT((b.center - box_->center).norm(), 0.5);
  EXPECT_LT(BoxYawErrorDeg(b.yaw_deg, box_->rotation), 3.0);
}

TEST(LocateStepsFit, FitSettingsFollowTheLocatorsOptions) {
  LocateOptions options;
  options.search_px = 5;
  options.min_edge_gradient = 6;
  options.edge_sigma = 0.6;
  options.camera_blur_px = 0.8;
  options.outer_iterations = 4;
  options.inner_iterations = 3;
  FitOptions fit = FitSettings(options, 100);
  EXPECT_EQ(fit.search_px, 5);
  EXPECT_EQ(fit.min_gradient, 25);  // a quarter of the strongest, above the floor
  EXPECT_NEAR(fit.edge_blur_px, 1.0, 1e-12);
  EXPECT_EQ(fit.outer_iterations, 4);
  EXPECT_EQ(fit.inner_iterations, 3);
  EXPECT_EQ(FitSettings(options, 10).min_gradient, 6);
}

TEST(LocateStepsFit, FitScoreAddsBothViewsResidualsAndTwiceTheMissedShare) {
  FitOutcome f;
  EXPECT_EQ(FitScore(f), 1e18);  // failed
  f.ok = true;
  f.rms_px = {0.2, 0.3};
  f.sampled = {100, 100};
  f.used = {90, 70};
  EXPECT_NEAR(FitScore(f), 0.5 + 2 * 0.2, 1e-12);
  f.sampled = {0, 0};
  f.used = {0, 0};
  EXPECT_NEAR(FitScore(f), 0.5 + 2.0, 1e-12);        // nothing sampled: all missed
  EXPECT_NEAR(FitScore(f, 0.5), 0.25 + 2.0, 1e-12);  // the residuals scaled, not the share
}

TEST(LocateStepsFit, TheSupportedScoreCountsOnlyTheOutlineThatShouldShowAnEdge) {
  FitOutcome f;
  f.ok = true;
  f.rms_px = {0.2, 0.3};
  f.sampled = {100, 100};
  f.used = {60, 70};  // 35% of the whole outline without an edge
  // Of the samples with a visible step, 10 of 80 and 5 of 70 without an edge.
  std::array<OutlineSupport, 2> support;
  support[0].contrasted = 80;
  support[0].edged = 70;
  support[1].contrasted = 70;
  support[1].edged = 65;
  EXPECT_NEAR(SupportedFitScore(f, support), 0.5 + 2 * 0.1, 1e-12);
  EXPECT_NEAR(SupportedFitScore(f, support, 0.5), 0.25 + 2 * 0.1, 1e-12);
  // No sample with a step: the whole outline's share, as FitScore.
  EXPECT_NEAR(SupportedFitScore(f, {}), FitScore(f), 1e-12);
  f.ok = false;
  EXPECT_EQ(SupportedFitScore(f, support), 1e18);
}

TEST(LocateStepsFit, TheScoresResidualsAreInTheReferenceCamerasPixels) {
  LocateOptions options;
  options.score_reference_width_px = 512;
  options.score_width_power = 0.5;
  EXPECT_NEAR(ScoreResidualScale(options, 512), 1.0, 1e-12);
  EXPECT_NEAR(ScoreResidualScale(options, 2048), 0.5, 1e-12);
  EXPECT_NEAR(ScoreResidualScale(options, 128), 2.0, 1e-12);
  options.score_width_power = 0;  // plain pixels
  EXPECT_NEAR(ScoreResidualScale(options, 1920), 1.0, 1e-12);
  options.score_reference_width_px = 0;
  std::string error;
  EXPECT_FALSE(options.Check(&error));
}

// --- 5. Both views ---

TEST(LocateStepsFit, CheckBothViewsNamesTheViewThatIsNotExplained) {
  LocateOptions options;
  options.min_inlier_share = 0.6;
  options.max_rms_px = 0.8;
  FitOutcome f;
  f.ok = true;
  f.sampled = {100, 100};
  f.used = {90, 50};
  f.rms_px = {0.3, 0.3};
  auto failure = CheckBothViews(f, options);
  ASSERT_TRUE(failure.has_value());
  EXPECT_EQ(failure->reason, Failure::kLeftRightInconsistent);
  EXPECT_TRUE(Contains(failure->detail, "only 50%")) << failure->detail;
  EXPECT_TRUE(Contains(failure->detail, "right image")) << failure->detail;
  f.used = {90, 90};
  f.rms_px = {0.9, 0.3};
  failure = CheckBothViews(f, options);
  ASSERT_TRUE(failure.has_value());
  EXPECT_TRUE(Contains(failure->detail, "misses the left image's edges by 0.90 px"))
      << failure->detail;
  f.rms_px = {0.3, 0.3};
  EXPECT_FALSE(CheckBothViews(f, options).has_value());
}

// --- The result ---

TEST(LocateStepsResult, CylinderFromFitGivesItsCentreSizeAndAnUpwardAxis) {
  Eigen::VectorXd x(7);
  x << 1, 2, 5, 1, 2, 1, -0.5;  // caps at z = 5 and z = 1, the radius's sign does not matter
  const CylinderResult c = CylinderFromFit(x, Eigen::MatrixXd::Zero(7, 7));
  EXPECT_TRUE(c.center.isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_DOUBLE_EQ(c.radius, 0.5);
  EXPECT_DOUBLE_EQ(c.height, 4);
  EXPECT_TRUE(c.axis.isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_EQ(c.radius_sigma, 0);
  // A level axis points along +x.
  x << 3, 0, 0, -1, 0, 0, 1;
  EXPECT_TRUE(
      CylinderFromFit(x, Eigen::MatrixXd::Zero(7, 7)).axis.isApprox(Eigen::Vector3d::UnitX()));
  // The deviations come from the covariance: the radius's own variance of 0.04.
  Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(7, 7);
  cov(6, 6) = 0.04;
  EXPECT_NEAR(CylinderFromFit(x, cov).radius_sigma, 0.2, 1e-6);
  EXPECT_NEAR(CylinderFromFit(x, cov).height_sigma, 0, 1e-6);
  // No size, no axis.
  x << 1, 1, 1, 1, 1, 1, 0.5;
  const CylinderResult flat = CylinderFromFit(x, Eigen::MatrixXd::Zero(7, 7));
  EXPECT_LT(flat.height, 1e-6);
  EXPECT_EQ(flat.axis, Eigen::Vector3d::UnitZ());
}

TEST(LocateStepsResult, BoxFromFitGivesTheCanonicalBoxAndItsExtent) {
  Eigen::VectorXd x(7);
  x << 1, 2, 3, 4, 2, 6, 0;
  BoxResult b = BoxFromFit(x, Eigen::MatrixXd::Zero(7, 7));
  EXPECT_TRUE(b.center.isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_TRUE(b.size.isApprox(Eigen::Vector3d(4, 2, 6)));
  EXPECT_NEAR(b.yaw_deg, 0, 1e-12);
  EXPECT_TRUE(b.min.isApprox(Eigen::Vector3d(-1, 1, 0)));
  EXPECT_TRUE(b.max.isApprox(Eigen::Vector3d(3, 3, 6)));
  // Turned a quarter turn and a bit: the same box turned a bit, its x and y sizes swapped.
  x[6] = (90 + 10) * M_PI / 180;
  b = BoxFromFit(x, Eigen::MatrixXd::Zero(7, 7));
  EXPECT_NEAR(b.yaw_deg, 10, 1e-9);
  EXPECT_NEAR(b.size.x(), 2, 1e-9);
  EXPECT_NEAR(b.size.y(), 4, 1e-9);
}

geometry::ProjectiveCamera SmallCamera() {
  // 256 x 192 pixels, focal length 400 px, at the origin looking along +y, z up.
  Eigen::Matrix3d K, R;
  K << 400, 0, 127.5, 0, 400, 95.5, 0, 0, 1;
  R << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  geometry::Matrix34 P;
  P.leftCols<3>() = K * R;
  P.col(3).setZero();
  return geometry::ProjectiveCamera(P, {256, 192});
}

TEST(LocateStepsResult, BoxTextureRectIsItsCornersBoundsAndFailsWhenOneHasNoImage) {
  const geometry::ProjectiveCamera camera = SmallCamera();
  const cv::Rect image(0, 0, 256, 192);
  Eigen::VectorXd x(7);
  x << 0, 40, 0, 4, 4, 4, 0;  // a 4 in cube 40 in ahead, centred in the view
  auto rect = BoxTextureRect(x, camera, image);
  ASSERT_TRUE(rect.ok()) << rect.failure().detail;
  // Its front face (at 38 in) spans 400 * 2 / 38 = 21.05 px either side of the centre.
  EXPECT_EQ(rect->x, static_cast<int>(std::floor(127.5 - 400.0 * 2 / 38)));
  EXPECT_EQ(rect->x + rect->width, static_cast<int>(std::ceil(127.5 + 400.0 * 2 / 38)) + 1);
  // Partly outside the image (u from 222.7 to 274.9): cut to it.
  x[0] = 12;
  rect = BoxTextureRect(x, camera, image);
  ASSERT_TRUE(rect.ok());
  EXPECT_EQ(rect->x, 222);
  EXPECT_EQ(rect->x + rect->width, 256);
  // Wholly outside: no pixels to cut.
  x[0] = 20;
  rect = BoxTextureRect(x, camera, image);
  ASSERT_TRUE(rect.ok());
  EXPECT_TRUE(rect->empty());
  // A corner in front of the camera yet at infinity in the image: no rectangle (this read an
  // empty projection before).
  x << 0, 40, 0, 4e24, 4, 4, 0;
  rect = BoxTextureRect(x, camera, image);
  ASSERT_FALSE(rect.ok());
  EXPECT_EQ(rect.failure().reason, Failure::kFitFailed);
  EXPECT_TRUE(Contains(rect.failure().detail, "does not project")) << rect.failure().detail;
}

TEST(LocateStepsResult, TheRangeIsCheckedAgainstTheLocatedCylinder) {
  LocateInput in;
  in.type = SolidType::kCylinder;
  in.ranger_origin = Eigen::Vector3d::Zero();
  in.ranger_axis = Eigen::Vector3d::UnitY();
  LocateOptions options;
  Eigen::VectorXd x(7);
  x << 0, 50, -3, 0, 50, 3, 2;  // upright, radius 2, its front at 48 in along the beam
  RangeCheck check;
  check.measured = 48.1;
  CheckRange(in, options, x, &check);
  EXPECT_TRUE(check.agrees) << check.detail;
  EXPECT_NEAR(check.expected_max, 48, 0.1);
  EXPECT_LE(check.expected_min, check.expected_max);

  check = RangeCheck{};
  check.measured = 44;
  CheckRange(in, options, x, &check);
  EXPECT_FALSE(check.agrees);
  EXPECT_TRUE(Contains(check.detail, "shorter than")) << check.detail;

  check = RangeCheck{};
  check.measured = 53;
  CheckRange(in, options, x, &check);
  EXPECT_FALSE(check.agrees);
  EXPECT_TRUE(Contains(check.detail, "beyond where the beam meets")) << check.detail;

  // Aimed away from it: the beam does not reach it.
  in.ranger_axis = Eigen::Vector3d::UnitX();
  check = RangeCheck{};
  check.measured = 48;
  CheckRange(in, options, x, &check);
  EXPECT_FALSE(check.agrees);
  EXPECT_TRUE(Contains(check.detail, "does not reach")) << check.detail;
}

}  // namespace
}  // namespace igms::object
