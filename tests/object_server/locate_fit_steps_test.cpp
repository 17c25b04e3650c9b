// Steps 4-5 of the locator (object_server/locate_steps.h) and its result on their own: the
// starting models and the fit on a rendered testbed scene, the scores and checks, and the
// result from known parameters. Steps 0-3: locate_steps_test.cpp.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "common/sim/site_scenes.h"
#include "object_server/locate_steps.h"
#include "object_server/solid_models.h"
#include "tests/object_server/locate_steps_fixture.h"

namespace igms::object {
namespace {

using testing::Contains;
using testing::CylinderOutlines;
using testing::LocateSteps;
using testing::MarkedSiteCylinder;
using testing::SiteCylinder;

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

  const std::array<FitView, 2> views = FitViews(in, t);
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

// A pipe raised on two blocks (site level "pipes", seed 10, 1920x1080) whose shaded lower limb
// shows no strong edge: the boundary's rectangle takes in the blocks, and only the starts from
// its upper limb lie near the pipe. An upright cylinder's limbs are vertical: no such starts.
// (Both also have starts from their boundary's upper part, which fit a pipe lying on a block.)
TEST_F(LocateSteps, ARaisedPipeStartsFromItsUpperLimbAndAnUprightDoesNot) {
  const SiteCylinder marked = MarkedSiteCylinder(10, site::SiteLevel::kPipes, true, "lying_0", 10);
  const site::Cylinder& pipe = marked.pipe;
  const LocateInput& in = marked.input;
  const Gradients* gradients = nullptr;
  const Through3 t = RunThroughStep3(in, &gradients);
  RaisedPipeStarts raised;
  const auto starts =
      CylinderStarts(t.pair, t.boundary.pixels, t.depth, t.search, options_, gradients, &raised);
  ASSERT_FALSE(starts.empty());
  const std::vector<Eigen::VectorXd>& upper = raised.upper_limb;
  ASSERT_EQ(upper.size(), 3u);
  EXPECT_FALSE(raised.upper_part.empty());
  // How far a start is from the pipe as the left image shows it: its axis's direction there
  // (the depth along it is the fit's to find) in units of 10 degrees, its radius in units of
  // 40%.
  const auto image_direction = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return Eigen::Vector2d(*in.left_camera.Project(b) - *in.left_camera.Project(a)).normalized();
  };
  const Eigen::Vector2d truth = image_direction(pipe.Base(), pipe.Top());
  const auto off = [&](const Eigen::VectorXd& x) {
    const Eigen::Vector2d d = image_direction(x.segment<3>(0), x.segment<3>(3));
    const double angle_deg = std::acos(std::min(1.0, std::abs(d.dot(truth)))) * 180 / M_PI;
    return std::max(angle_deg / 10, std::abs(x[6] - pipe.radius) / (0.4 * pipe.radius));
  };
  double best_upper = 1e9, best_other = 1e9;
  for (const auto& x : upper) best_upper = std::min(best_upper, off(x));
  for (const auto& x : starts) best_other = std::min(best_other, off(x));
  // One within 10 degrees and 40% of the radius; none of the other starts.
  EXPECT_LT(best_upper, 1.0);
  EXPECT_GT(best_other, 1.0);

  const LocateInput upright = Input(true);
  const Through3 u = RunThroughStep3(upright, &gradients);
  RaisedPipeStarts upright_raised;
  CylinderStarts(u.pair, u.boundary.pixels, u.depth, u.search, options_, gradients,
                 &upright_raised);
  EXPECT_TRUE(upright_raised.upper_limb.empty());
}

// A fitted pipe whose top no edge held (its sigma along the axis 100 in) 1 in above the
// truth: the top moves to where both images' limbs end, with a sigma along the axis of a few
// pixels; the bottom, held, stays. With both ends held, or marks that end across the pipe,
// nothing moves; a held top short of the truth moves up to where the limbs end.
TEST_F(LocateSteps, AnUnheldEndMovesToWhereTheLimbsEnd) {
  const LocateInput in = Input(true);
  const Through3 t = RunThroughStep3(in);
  const std::array<FitView, 2> views = FitViews(in, t);
  const FitOptions fit = FitSettings(options_, t.boundary.strongest);
  const Eigen::Vector3d base = cylinder_->Base(), top = cylinder_->Top();
  FitOutcome f;
  f.ok = true;
  f.params.resize(7);
  f.params << base, top + 1.0 * cylinder_->axis, cylinder_->radius;
  f.covariance = Eigen::MatrixXd::Identity(7, 7) * 1e-4;
  f.outline = CylinderOutlines(f.params, views);
  FitOutcome held = f;
  EndsFromLimbs(views, fit, options_, &held);
  EXPECT_EQ(held.params, f.params);
  // A held top 1 in short of the truth, as on a band of another shade across the pipe: the
  // limbs run past it in both images, and it moves up to where they end.
  FitOutcome short_top = f;
  short_top.params.segment<3>(3) = top - 1.0 * cylinder_->axis;
  short_top.outline = CylinderOutlines(short_top.params, views);
  EndsFromLimbs(views, fit, options_, &short_top);
  EXPECT_LT((short_top.params.segment<3>(3) - top).norm(), 0.1);

  f.covariance(5, 5) = 100.0 * 100.0;  // the top's height: the axis is vertical
  // Marks whose top cuts the pipe three quarters up: the limbs run on to their border, which
  // says nothing of where the pipe ends.
  std::array<FitView, 2> cut = views;
  for (int v = 0; v < 2; ++v) {
    const Eigen::Vector2d low = *views[v].camera->Project(base),
                          high = *views[v].camera->Project(base + 0.75 * (top - base));
    const double half_width = 40;
    cut[v].region = {{low.x() - half_width, low.y() + 20},
                     {low.x() + half_width, low.y() + 20},
                     {high.x() + half_width, high.y()},
                     {high.x() - half_width, high.y()}};
    if (SignedDistance(cut[v].region, low + Eigen::Vector2d(0, -10)) > 0)  // clockwise in u-v
      std::reverse(cut[v].region.begin(), cut[v].region.end());
  }
  FitOutcome at_border = f;
  EndsFromLimbs(cut, fit, options_, &at_border);
  EXPECT_EQ(at_border.params, f.params);

  EndsFromLimbs(views, fit, options_, &f);
  EXPECT_LT((f.params.segment<3>(3) - top).norm(), 0.1);
  EXPECT_LT((f.params.segment<3>(0) - base).norm(), 1e-9);
  EXPECT_GT(std::sqrt(f.covariance(5, 5)), 0.005);
  EXPECT_LT(std::sqrt(f.covariance(5, 5)), 0.3);
  const CylinderResult c = CylinderFromFit(f.params, f.covariance);
  EXPECT_NEAR(c.height, cylinder_->height, 0.1);
  EXPECT_LT(c.height_sigma, 0.3);
}

// An upright pipe standing in front of the table's far edge (site level "clutter", seed 4,
// the thesis's cameras): below that edge it has the table's shade, and its limbs fade there.
// Its foot, unheld, stays where the fit left it rather than move up short of the truth; its
// top, unheld too, against the black above, moves to where the limbs end. Within the marks,
// the foot's sigma comes from how far apart the limbs' end and the marks' border lie.
TEST_F(LocateSteps, AnUnheldEndStaysWhereTheBackgroundChangesBesideTheLimbsEnd) {
  const SiteCylinder marked =
      MarkedSiteCylinder(4, site::SiteLevel::kClutter, false, "upright_8", 4);
  const site::Cylinder& pipe = marked.pipe;
  const LocateInput& in = marked.input;
  const Through3 t = RunThroughStep3(in);
  const std::array<FitView, 2> views = FitViews(in, t);
  const Eigen::Vector3d base = pipe.Base(), top = pipe.Top();
  FitOutcome f;
  f.ok = true;
  f.params.resize(7);
  f.params << base - 0.3 * pipe.axis, top + 0.3 * pipe.axis, pipe.radius;
  f.covariance = Eigen::MatrixXd::Identity(7, 7) * 1e-4;
  f.covariance(2, 2) = f.covariance(5, 5) = 100.0 * 100.0;
  f.outline = CylinderOutlines(f.params, views);
  const Eigen::Vector3d foot = f.params.segment<3>(0);
  const FitOptions fit = FitSettings(options_, t.boundary.strongest);
  FitOutcome unbounded = f;
  EndsFromLimbs(views, fit, options_, &unbounded);
  EXPECT_LT((unbounded.params.segment<3>(0) - foot).norm(), 1e-9);
  EXPECT_GT(std::sqrt(unbounded.covariance(2, 2)), 50.0);
  EXPECT_LT((unbounded.params.segment<3>(3) - top).norm(), 0.1);
  EXPECT_LT(std::sqrt(unbounded.covariance(5, 5)), 0.3);
  // With the marks bounding the outline, as Locate bounds it: the foot lies between the
  // limbs' end and the marks' border, and its sigma says so (it is 0.3 in off).
  std::array<FitView, 2> bounded = views;
  const auto regions = OutlineRegions(t.marks, t.pair, t.depth - 1.5, t.depth + 4.5, options_);
  for (int v = 0; v < 2; ++v) bounded[v].region = regions[v];
  EndsFromLimbs(bounded, fit, options_, &f);
  EXPECT_LT((f.params.segment<3>(0) - foot).norm(), 1e-9);
  EXPECT_GT(std::sqrt(f.covariance(2, 2)), 0.15);
  EXPECT_LT(std::sqrt(f.covariance(2, 2)), 3.0);
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

  const std::array<FitView, 2> views = FitViews(in, t);
  const FitOutcome f = FitBox(starts, views, FitSettings(options_, t.boundary.strongest), options_);
  ASSERT_TRUE(f.ok) << f.error;
  ASSERT_EQ(f.params.size(), 7);
  EXPECT_EQ(f.covariance.rows(), 7);
  EXPECT_FALSE(CheckBothViews(f, options_).has_value());
  const BoxResult b = BoxFromFit(f.params, f.covariance);
  EXPECT_LT((b.center - box_->center).norm(), 0.5);
  EXPECT_LT(BoxYawErrorDeg(b.yaw_deg, box_->rotation), 3.0);
}

TEST_F(LocateSteps, AnAlignedBlocksEdgesShowNoTurn) {
  const LocateInput in = Input(false);
  const Gradients* grad = nullptr;
  const Through3 t = RunThroughStep3(in, &grad);
  ASSERT_NEAR(std::atan2(box_->rotation(1, 0), box_->rotation(0, 0)), 0.0, 1e-9);
  const auto yaws = HorizontalEdgeYaws(in.left_camera, t.boundary.pixels, t.depth, *grad, 2);
  ASSERT_FALSE(yaws.empty());
  EXPECT_NEAR(yaws[0] * 180 / M_PI, 0.0, 3.0);
  for (const auto& s : BoxStarts(in.left_camera, t.boundary.pixels, t.depth, grad))
    EXPECT_EQ(s[6], 0.0);
}

// The same scene with its block turned by 30 degrees about the vertical.
class TurnedBlockSteps : public LocateSteps {
 protected:
  static void SetUpTestSuite() {
    scene_ = new site::Scene(site::RandomTestbedScene(42));
    for (auto& o : scene_->objects)
      if (auto* b = std::get_if<site::Box>(&o.shape)) {
        b->rotation = Eigen::AngleAxisd(30 * M_PI / 180, Eigen::Vector3d::UnitZ()).matrix();
        break;
      }
    images_ = new site::StereoImages(site::RenderStereo(*scene_));
  }
};

TEST_F(TurnedBlockSteps, ATurnedBlockStartsAtTheYawItsEdgesShowAndFitsOntoIt) {
  const LocateInput in = Input(false);
  const Gradients* grad = nullptr;
  const Through3 t = RunThroughStep3(in, &grad);
  const auto yaws = HorizontalEdgeYaws(in.left_camera, t.boundary.pixels, t.depth, *grad, 2);
  ASSERT_FALSE(yaws.empty());
  EXPECT_NEAR(yaws[0] * 180 / M_PI, 30.0, 3.0);

  const auto starts = BoxStarts(in.left_camera, t.boundary.pixels, t.depth, grad);
  std::vector<Eigen::VectorXd> turned;
  for (const auto& s : starts)
    if (s[6] != 0.0) turned.push_back(s);
  ASSERT_FALSE(turned.empty());
  // The turned start from the silhouette's corner, sides and top: near the block before any
  // fit (sizes along the box's own axes, x along the yaw), within half its size (the depth
  // matched on its faces puts it a little far).
  const Eigen::VectorXd& s = turned[0];
  EXPECT_NEAR(s[6], yaws[0], 1e-12);
  EXPECT_LT((s.head<3>() - box_->center).norm(), 0.5 * box_->size.maxCoeff());
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(s[3 + k], box_->size[k], 0.2 * box_->size[k]) << k;

  const std::array<FitView, 2> views = FitViews(in, t);
  const FitOutcome f = FitBox(starts, views, FitSettings(options_, t.boundary.strongest), options_);
  ASSERT_TRUE(f.ok) << f.error;
  const BoxResult b = BoxFromFit(f.params, f.covariance);
  EXPECT_LT((b.center - box_->center).norm(), 0.3);
  EXPECT_LT(BoxYawErrorDeg(b.yaw_deg, box_->rotation), 1.5);

  // Turned starts alone, as a turned block lowered or stood on the floor gives: no start at
  // yaw 0 for the aligned fit, so the box is turned from the first start; it lands the same.
  const FitOutcome g = FitBox(turned, views, FitSettings(options_, t.boundary.strongest), options_);
  ASSERT_TRUE(g.ok) << g.error;
  const BoxResult bg = BoxFromFit(g.params, g.covariance);
  EXPECT_LT((bg.center - box_->center).norm(), 0.3);
  EXPECT_LT(BoxYawErrorDeg(bg.yaw_deg, box_->rotation), 1.5);
  // No start at all is a failure that says so, not a fit from nothing.
  const FitOutcome none = FitFromStarts(BoxOutline, {}, {}, views, FitSettings(options_, 100));
  EXPECT_FALSE(none.ok);
  EXPECT_EQ(none.error, "no starting model to fit from");
  const FitOutcome no_box = FitBox({}, views, FitSettings(options_, 100), options_);
  EXPECT_FALSE(no_box.ok);
  EXPECT_EQ(no_box.error, "no starting model to fit from");
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

// Wider images have more outline samples per length of edge, sharing their errors: the fit
// counts them as correlated in proportion, and never fewer than at the reference width.
TEST(LocateStepsFit, WiderImagesCountTheirSamplesAsMoreCorrelated) {
  LocateOptions options;
  const double base = FitOptions{}.correlated_samples;
  EXPECT_EQ(FitSettings(options, 100).correlated_samples, base);
  EXPECT_EQ(FitSettings(options, 100, 512).correlated_samples, base);
  EXPECT_EQ(FitSettings(options, 100, 320).correlated_samples, base);
  EXPECT_NEAR(FitSettings(options, 100, 1920).correlated_samples, base * 1920 / 512, 1e-9);
  options.sigma_width_power = 0.5;
  EXPECT_NEAR(FitSettings(options, 100, 2048).correlated_samples, base * 2, 1e-9);
  options.sigma_width_power = -1;
  std::string error;
  EXPECT_FALSE(options.Check(&error));
}

TEST_F(LocateSteps, TheOtherTypeIsFittedAsItWouldBeWereItAskedFor) {
  // Each object asked for as either type: the score of the type tried as the other one is
  // the score that type's own request reaches, so neither is held against a lesser fit. (A
  // pipe asked for also tries starts from its boundary's upper part, a pipe lying on a block,
  // which the other type does not: there it may score better than as the other type.)
  for (const bool on_cylinder : {true, false}) {
    LocateInput in = Input(on_cylinder);
    in.type = SolidType::kCylinder;
    const LocateResult as_cylinder = Locate(in);
    in.type = SolidType::kBox;
    const LocateResult as_box = Locate(in);
    ASSERT_GE(as_box.other_type_fit_score, 0) << on_cylinder;  // a box always tries a cylinder
    if (on_cylinder)
      EXPECT_NEAR(as_box.other_type_fit_score, as_cylinder.fit_score, 1e-9);
    else
      EXPECT_GE(as_box.other_type_fit_score, as_cylinder.fit_score - 1e-9);
    if (as_cylinder.other_type_fit_score >= 0) {
      EXPECT_NEAR(as_cylinder.other_type_fit_score, as_box.fit_score, 1e-9) << on_cylinder;
    }
    // Each is found as what it is, and refused as the other.
    EXPECT_EQ(as_cylinder.found, on_cylinder) << as_cylinder.detail;
    EXPECT_EQ(as_box.found, !on_cylinder) << as_box.detail;
  }
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

TEST(LocateStepsFit, APartialBoxIsNotHeldAgainstACylinderButEveryCylinderAgainstABox) {
  const LocateOptions options;
  FitOutcome loose, tight;  // scores 1.0 and 0.3: 0.3 is over 1.5 times better
  loose.ok = tight.ok = true;
  loose.rms_px = {0.3, 0.3};
  tight.rms_px = {0.1, 0.1};
  loose.sampled = tight.sampled = {100, 100};
  loose.used = {80, 80};
  tight.used = {95, 95};
  ASSERT_NEAR(FitScore(loose), 1.0, 1e-12);
  ASSERT_NEAR(FitScore(tight), 0.3, 1e-12);
  // The supported scores taken equal to the scores, but where said.
  const auto check = [&](bool cylinder, const FitOutcome& f, const FitOutcome& other,
                         bool other_within_marks, SideShape side) {
    return CheckOtherType(cylinder, f, other, other_within_marks, side,
                          {FitScore(f), FitScore(other), FitScore(f), FitScore(other)}, options);
  };
  // A cylinder against a box that explains the outline much better: refused, unless that box
  // leaves part of the marks empty (the top half of a pipe standing against the table).
  const auto refused = check(true, loose, tight, true, SideShape::kRound);
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->reason, Failure::kFitFailed);
  EXPECT_NE(refused->detail.find("is the object a box?"), std::string::npos) << refused->detail;
  EXPECT_FALSE(check(true, loose, tight, false, SideShape::kRound).has_value());
  // A box must beat the cylinder, wherever the cylinder lies.
  EXPECT_TRUE(check(false, loose, tight, true, SideShape::kUnmeasured).has_value());
  EXPECT_TRUE(check(false, loose, tight, false, SideShape::kUnmeasured).has_value());
  EXPECT_FALSE(check(false, tight, loose, false, SideShape::kUnmeasured).has_value());
  // A failed other fit says nothing.
  FitOutcome failed;
  EXPECT_FALSE(check(true, loose, failed, true, SideShape::kRound).has_value());
  // A cylinder whose side shades flat: refused when a box fits at all, however much worse.
  FitOutcome middling = tight;  // score 0.5
  middling.rms_px = {0.15, 0.15};
  middling.used = {90, 90};
  ASSERT_NEAR(FitScore(middling), 0.5, 1e-12);
  EXPECT_FALSE(check(true, tight, middling, true, SideShape::kRound));
  const auto flat = check(true, tight, middling, true, SideShape::kFlat);
  ASSERT_TRUE(flat.has_value());
  EXPECT_NE(flat->detail.find("shades flat"), std::string::npos) << flat->detail;
  EXPECT_FALSE(check(true, tight, middling, false, SideShape::kFlat));
  EXPECT_FALSE(check(true, tight, loose, true, SideShape::kFlat));  // over 0.9
  EXPECT_FALSE(check(true, tight, failed, true, SideShape::kFlat));
  // One creased: refused whatever the box.
  const auto creased = check(true, tight, failed, true, SideShape::kCreased);
  ASSERT_TRUE(creased.has_value());
  EXPECT_NE(creased->detail.find("crease"), std::string::npos) << creased->detail;
  // A cylinder a box beats much on the outline that should show an edge only: refused, unless
  // the box explains the images too poorly to be reported itself.
  const auto on_supported =
      CheckOtherType(true, tight, middling, true, SideShape::kRound, {0.3, 0.5, 0.4, 0.2}, options);
  ASSERT_TRUE(on_supported.has_value());
  EXPECT_NE(on_supported->detail.find("is the object a box?"), std::string::npos);
  EXPECT_FALSE(CheckOtherType(true, tight, middling, true, SideShape::kRound, {0.3, 1.0, 0.4, 0.2},
                              options));
  EXPECT_FALSE(CheckOtherType(true, tight, middling, true, SideShape::kRound, {0.3, 0.5, 0.4, 0.3},
                              options));
  // One whose side shades clearly round is held against the box on that outline alone.
  EXPECT_TRUE(check(true, loose, tight, true, SideShape::kRound).has_value());
  EXPECT_FALSE(CheckOtherType(true, loose, tight, true, SideShape::kClearlyRound,
                              {1.0, 0.3, 0.3, 0.3}, options));
  EXPECT_TRUE(CheckOtherType(true, loose, tight, true, SideShape::kClearlyRound,
                             {1.0, 0.3, 0.5, 0.3}, options));
  // A box beating the cylinder's score but not on the outline that should show an edge:
  // refused; not against a "cylinder" whose side is creased, nor one that explains the images
  // too poorly to be reported itself (over max_fit_score).
  const TypeScores worse_supported{0.3, 0.5, 0.3, 0.25};
  const auto tie =
      CheckOtherType(false, tight, middling, true, SideShape::kRound, worse_supported, options);
  ASSERT_TRUE(tie.has_value());
  EXPECT_NE(tie->detail.find("is the object a cylinder?"), std::string::npos) << tie->detail;
  // The same against a rival whose side shades flat, as a block's face seen square on: still
  // refused, and the operator told why the images cannot settle it.
  for (const SideShape flat_side : {SideShape::kFlat, SideShape::kEven}) {
    const auto square_on =
        CheckOtherType(false, tight, middling, true, flat_side, worse_supported, options);
    ASSERT_TRUE(square_on.has_value());
    EXPECT_NE(square_on->detail.find("cannot tell a block from a pipe standing up"),
              std::string::npos)
        << square_on->detail;
  }
  EXPECT_FALSE(CheckOtherType(false, tight, middling, true, SideShape::kRound,
                              {0.3, 0.5, 0.2, 0.25}, options));
  // Against a cylinder whose side shades clearly round, a box must beat it by
  // box_over_cylinder on the outline that should show an edge too; unless that cylinder does
  // not fit (over max_fit_score, or beyond the marks).
  const TypeScores a_little_better{0.3, 0.5, 0.22, 0.25};
  EXPECT_FALSE(
      CheckOtherType(false, tight, middling, true, SideShape::kRound, a_little_better, options));
  const auto round = CheckOtherType(false, tight, middling, true, SideShape::kClearlyRound,
                                    a_little_better, options);
  ASSERT_TRUE(round.has_value());
  EXPECT_NE(round->detail.find("shades round"), std::string::npos) << round->detail;
  EXPECT_FALSE(CheckOtherType(false, tight, middling, true, SideShape::kClearlyRound,
                              {0.3, 0.5, 0.19, 0.25}, options));
  EXPECT_FALSE(CheckOtherType(false, tight, middling, false, SideShape::kClearlyRound,
                              a_little_better, options));
  EXPECT_FALSE(CheckOtherType(false, tight, loose, true, SideShape::kClearlyRound,
                              {0.3, 1.0, 0.22, 0.25}, options));
  EXPECT_FALSE(
      CheckOtherType(false, tight, middling, true, SideShape::kCreased, worse_supported, options));
  EXPECT_FALSE(
      CheckOtherType(false, tight, loose, true, SideShape::kRound, {0.3, 1.0, 0.3, 0.25}, options));
  EXPECT_FALSE(CheckOtherType(false, loose, tight, true, SideShape::kCreased, {1.0, 0.3, 1.0, 0.3},
                              options));
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

TEST(KnownSteps, ABlockWithItsTopHiddenReachesUpToThePipeItCarries) {
  BoxResult box;
  box.center = {0, 0, 1};
  box.size = {1, 1, 2};
  box.min = {-0.5, -0.5, 0};
  box.min_sigma = {0.02, 0.02, 0.02};
  box.size_sigma = {0.03, 0.03, 50};  // the top held by no edge
  // A pipe of radius 0.5 lying along x over the block, its underside at 2.5; another beside.
  KnownShape pipe{"pipe", SolidType::kCylinder, Eigen::VectorXd(7), 0.03};
  pipe.params << -4, 0.2, 3, 4, 0.2, 3, 0.5;
  KnownShape beside = pipe;
  beside.params[1] = beside.params[4] = 5;
  BoxResult reached = box;
  ReachUpToKnown({beside, pipe}, LocateOptions{}, &reached);
  EXPECT_NEAR(reached.size.z(), 2.5, 1e-12);
  EXPECT_NEAR(reached.center.z(), 1.25, 1e-12);
  EXPECT_NEAR(reached.max.z(), 2.5, 1e-12);
  EXPECT_NEAR(reached.size_sigma.z(), std::hypot(0.02, 0.03), 1e-12);
  // Nothing over it, or a height the edges hold: left as it is.
  BoxResult alone = box;
  ReachUpToKnown({beside}, LocateOptions{}, &alone);
  EXPECT_EQ(alone.size.z(), 2);
  BoxResult held = box;
  held.size_sigma.z() = 0.05;
  ReachUpToKnown({pipe}, LocateOptions{}, &held);
  EXPECT_EQ(held.size.z(), 2);
}

}  // namespace
}  // namespace igms::object
