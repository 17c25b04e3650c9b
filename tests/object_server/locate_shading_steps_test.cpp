// How a pipe's side shades (object_server/locate_steps.h: MeasureSideShading, ClassifySide),
// and the locator refusing a block asked for as a pipe on it, or a pipe a block asked for
// stands against: on rendered site scenes, with two lights and shadows, pipes round and blocks
// flat or creased.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string>
#include <variant>

#include "common/sim/marks.h"
#include "common/sim/renderer.h"
#include "common/sim/site_scenes.h"
#include "common/sim/vision/evaluation.h"
#include "object_server/locate_steps.h"

namespace igms::object {
namespace {

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

Eigen::VectorXd PipeParams(const site::Cylinder& c) {
  Eigen::VectorXd x(7);
  x << c.Base(), c.Top(), c.radius;
  return x;
}

// The upright pipe a block's front could be: its axis the block's, its radius half the
// block's narrower side.
Eigen::VectorXd PipeInBlock(const site::Box& b) {
  const Eigen::Vector3d up = b.rotation.col(2) * (0.5 * b.size.z());
  Eigen::VectorXd x(7);
  x << b.center - up, b.center + up, 0.5 * std::min(b.size.x(), b.size.y());
  return x;
}

// A site scene rendered, with an object of it asked for as `type` with the marks the
// benchmark's wrong-type requests use (common/sim/vision/evaluation.h).
struct Asked {
  site::Scene scene;
  LocateInput input;
  const site::Shape* shape = nullptr;
};
Asked AskFor(uint64_t seed, site::SiteLevel level, bool hd, const std::string& name,
             SolidType type) {
  Asked a;
  a.scene = site::SiteScene(seed, level, hd);
  const site::StereoImages images = site::RenderStereo(a.scene);
  for (size_t i = 0; i < a.scene.objects.size(); ++i) {
    if (a.scene.objects[i].name != name) continue;
    a.shape = &a.scene.objects[i].shape;
    a.input.marks = *site::GenerateMarks(*a.shape, a.scene.cameras.left, seed * 1000 + i);
  }
  if (!name.empty()) {
    EXPECT_NE(a.shape, nullptr) << name;
  }
  a.input.type = type;
  a.input.left = images.left;
  a.input.right = images.right;
  a.input.left_camera = a.scene.cameras.left;
  a.input.right_camera = a.scene.cameras.right;
  return a;
}

// The options the lab locates with on the site: its floor known (a rival pipe stands on it).
LocateOptions LabOptions() {
  LocateOptions o;
  o.floor_height = 0.0;
  return o;
}

std::array<FitView, 2> Views(const LocateInput& in) {
  return {FitView(&in.left_camera, nullptr), FitView(&in.right_camera, nullptr)};
}

TEST(SideShading, PipesInFullViewShadeRound) {
  // Level pipes with the thesis's cameras: pipes lying, raised and upright, two lights, shadows.
  const LocateOptions opt;
  int round = 0, unmeasured = 0;
  for (const auto level : {site::SiteLevel::kPipes, site::SiteLevel::kClutter})
    for (uint64_t seed = 1; seed <= 10; ++seed) {
      const Asked a = AskFor(seed, level, false, "", SolidType::kCylinder);
      const auto pair = PrepareImages(a.input);
      ASSERT_TRUE(pair.ok());
      const std::vector<double> left = site::VisibleFractions(a.scene, a.scene.cameras.left);
      const std::vector<double> right = site::VisibleFractions(a.scene, a.scene.cameras.right);
      for (size_t i = 0; i < a.scene.objects.size(); ++i) {
        const auto* c = std::get_if<site::Cylinder>(&a.scene.objects[i].shape);
        if (!c || std::min(left[i], right[i]) < 0.95) continue;
        const SideShape side = ClassifySide(*pair, PipeParams(*c), Views(a.input), opt);
        EXPECT_TRUE(side == SideShape::kRound || side == SideShape::kClearlyRound ||
                    side == SideShape::kFaintlyRound || side == SideShape::kUnmeasured)
            << "seed " << seed << " " << a.scene.objects[i].name;
        round += side == SideShape::kRound || side == SideShape::kClearlyRound ||
                 side == SideShape::kFaintlyRound;
        unmeasured += side == SideShape::kUnmeasured;
      }
    }
  // Pipes seen end on, or under 8 px across, are not measured.
  EXPECT_GE(round, 20);
  EXPECT_LE(unmeasured, round);
}

TEST(SideShading, ABlocksFrontShadesFlat) {
  // Level far, seed 5, the thesis's cameras: box_6 stands face on.
  const Asked a = AskFor(5, site::SiteLevel::kFar, false, "box_6", SolidType::kCylinder);
  ASSERT_NE(a.shape, nullptr);
  const auto pair = PrepareImages(a.input);
  ASSERT_TRUE(pair.ok());
  const LocateOptions opt;
  const Eigen::VectorXd block = PipeInBlock(std::get<site::Box>(*a.shape));
  EXPECT_EQ(ClassifySide(*pair, block, Views(a.input), opt), SideShape::kFlat);
  const SideShading sh = MeasureSideShading(pair->left, a.input.left_camera, block, {});
  ASSERT_TRUE(sh.measured);
  EXPECT_GE(sh.bins, 8);
  EXPECT_LT(sh.flat_rss, opt.flat_side_gain * sh.smooth_rss);
  // Hidden everywhere (a known solid in front): nothing to measure.
  const std::vector<std::vector<Eigen::Vector2d>> everywhere{
      {{-1e4, -1e4}, {1e4, -1e4}, {1e4, 1e4}, {-1e4, 1e4}}};
  EXPECT_FALSE(MeasureSideShading(pair->left, a.input.left_camera, block, everywhere).measured);
}

// Refused (fit failed) with a detail holding `phrase`, the rule's; reported found with the
// rule off (`without`).
void ExpectRefusedByTheRuleAlone(const LocateInput& in, const std::string& phrase,
                                 const LocateOptions& without) {
  const LocateResult refused = Locate(in);
  EXPECT_FALSE(refused.found);
  EXPECT_EQ(refused.reason, Failure::kFitFailed);
  EXPECT_TRUE(Contains(refused.detail, phrase)) << refused.detail;
  EXPECT_TRUE(Locate(in, without).found);
}

// LocateOptions::Check refuses `bad`, naming `option`.
void ExpectCheckNames(const LocateOptions& bad, const std::string& option) {
  std::string error;
  EXPECT_FALSE(bad.Check(&error));
  EXPECT_TRUE(Contains(error, option)) << error;
}

TEST(SideShading, ABlockAskedForAsAPipeIsRefusedWhenItsSideShadesFlat) {
  const Asked a = AskFor(5, site::SiteLevel::kFar, false, "box_6", SolidType::kCylinder);
  ASSERT_NE(a.shape, nullptr);
  // Without the rule a pipe explains the block's outline well enough to be reported.
  LocateOptions off;
  off.flat_side_gain = 0;
  ExpectRefusedByTheRuleAlone(a.input, "shades flat", off);
}

TEST(SideShading, ABlockAskedForAsAPipeIsRefusedWhenItsSideShadesEven) {
  // Level pipes, seed 5002, 1920x1080: support_2, under a pipe, seen square on. No box fits
  // its outline well enough to hold against the pipe, so the flat side alone does not refuse
  // it; its side shows no shading at all (a pipe's would, lit).
  const Asked a = AskFor(5002, site::SiteLevel::kPipes, true, "support_2", SolidType::kCylinder);
  ASSERT_NE(a.shape, nullptr);
  LocateOptions off;
  off.even_side_gain = 0;
  ExpectRefusedByTheRuleAlone(a.input, "shades flat and even", off);
  off.even_side_gain = -1;
  ExpectCheckNames(off, "even_side_gain");
}

TEST(SideShading, APipeWhoseSideShadesFaintlyRoundIsRefusedWhenABoxExplainsBothOutlinesBetter) {
  LocateOptions options;
  FitOutcome pipe, box;  // both fitted; the scores are given below
  pipe.ok = box.ok = true;
  pipe.sampled = box.sampled = {100, 100};
  pipe.used = box.used = {100, 100};
  // The box explains the whole outline and the part that should show an edge a little better
  // (0.45 against 0.5, 0.27 against 0.3: within faint_round_box_ratio, 0.9).
  const TypeScores better{0.5, 0.45, 0.3, 0.27};
  const auto faint =
      CheckOtherType(true, pipe, box, true, SideShape::kFaintlyRound, better, options);
  ASSERT_TRUE(faint.has_value());
  EXPECT_EQ(faint->reason, Failure::kFitFailed);
  EXPECT_NE(faint->detail.find("only faintly round"), std::string::npos) << faint->detail;
  EXPECT_NE(faint->detail.find("is the object a box?"), std::string::npos) << faint->detail;
  // A side that shades round beyond faint_round_side_gain keeps the pipe; so does a box no
  // better on either outline, or one that leaves the marks empty.
  EXPECT_FALSE(CheckOtherType(true, pipe, box, true, SideShape::kRound, better, options));
  EXPECT_FALSE(CheckOtherType(true, pipe, box, true, SideShape::kFaintlyRound,
                              {0.5, 0.46, 0.3, 0.2}, options));
  EXPECT_FALSE(CheckOtherType(true, pipe, box, true, SideShape::kFaintlyRound,
                              {0.5, 0.3, 0.3, 0.28}, options));
  EXPECT_FALSE(CheckOtherType(true, pipe, box, false, SideShape::kFaintlyRound, better, options));
  // A block asked for is not refused by it.
  EXPECT_FALSE(CheckOtherType(false, box, pipe, true, SideShape::kFaintlyRound,
                              {0.45, 0.5, 0.27, 0.3}, options));
  // The bounds are checked.
  std::string error;
  options.faint_round_side_gain = options.round_side_gain * 2;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_NE(error.find("faint_round_side_gain"), std::string::npos) << error;
  options = LocateOptions();
  options.faint_round_box_ratio = 1.5;
  EXPECT_FALSE(options.Check(&error));
}

TEST(SideShading, ABlockAskedForAsAPipeIsRefusedWhenItsSideShadesFaintlyRound) {
  // Level clutter, seed 40, the thesis's cameras: support_1, under a pipe. The pipe fitted to
  // it shades round, but under 20 times better than flat, and a box explains both its whole
  // outline and the part that should show an edge better (0.39 against 0.52, 0.35 against
  // 0.47): without the rule, the block was reported found as a pipe.
  const Asked a = AskFor(40, site::SiteLevel::kClutter, false, "support_1", SolidType::kCylinder);
  ASSERT_NE(a.shape, nullptr);
  const LocateResult refused = Locate(a.input, LabOptions());
  EXPECT_FALSE(refused.found);
  EXPECT_EQ(refused.reason, Failure::kFitFailed);
  EXPECT_TRUE(Contains(refused.detail, "only faintly round")) << refused.detail;
  LocateOptions off = LabOptions();
  off.faint_round_side_gain = 0;
  EXPECT_TRUE(Locate(a.input, off).found);
}

TEST(SideShading, ABlockAskedForAsAPipeIsRefusedWhenACreaseRunsAlongItsSide) {
  // Level far, seed 7, 1920x1080: box_11 turned to show two faces lit 46 grey levels apart.
  const Asked a = AskFor(7, site::SiteLevel::kFar, true, "box_11", SolidType::kCylinder);
  ASSERT_NE(a.shape, nullptr);
  const LocateResult as_pipe = Locate(a.input, LabOptions());
  EXPECT_FALSE(as_pipe.found);
  EXPECT_TRUE(Contains(as_pipe.detail, "crease")) << as_pipe.detail;
  // Not creased, a crease is still not round: the side counts as flat, and a box fits.
  LocateOptions no_crease = LabOptions();
  no_crease.crease_gain = 1e300;
  const LocateResult flat = Locate(a.input, no_crease);
  EXPECT_FALSE(flat.found);
  EXPECT_TRUE(Contains(flat.detail, "shades flat")) << flat.detail;
  // Without either rule the shading says nothing (a box still explains the outline that should
  // show an edge much better).
  no_crease.flat_side_gain = 0;
  const LocateResult without = Locate(a.input, no_crease);
  EXPECT_FALSE(Contains(without.detail, "shades") || Contains(without.detail, "crease"))
      << without.detail;
}

// The block's size error along its own axes (a quarter turn swaps x and y).
Eigen::Vector3d SizeError(const BoxResult& found, const site::Box& truth) {
  Eigen::Vector3d size = truth.size;
  const double yaw_deg = std::atan2(truth.rotation(1, 0), truth.rotation(0, 0)) * 180 / M_PI;
  if (std::abs(std::remainder(found.yaw_deg - yaw_deg, 180.0)) > 45) std::swap(size.x(), size.y());
  return (found.size - size).cwiseAbs();
}

TEST(SideShading, ABlockSeenSquareOnIsFoundWithItsDepthLeftOpen) {
  // Level far, seed 28: box_2, 78 in away, its top above the cameras, seen square on: one face
  // shows, flat, and an upright pipe explains its outline about as well. Nothing in the images
  // holds its depth, and the fit says so: found, its depth off within its sigma.
  const Asked a = AskFor(28, site::SiteLevel::kFar, false, "box_2", SolidType::kBox);
  ASSERT_NE(a.shape, nullptr);
  const auto& truth = std::get<site::Box>(*a.shape);
  const LocateResult r = Locate(a.input, LabOptions());
  ASSERT_TRUE(r.found) << r.detail;
  const Eigen::Vector3d error = SizeError(r.box, truth);
  const int depth = r.box.size_sigma.x() > r.box.size_sigma.y() ? 0 : 1;
  EXPECT_GE(r.box.size_sigma[depth], LabOptions().min_open_depth_sigma);
  EXPECT_LT(error[1 - depth], 0.1);
  EXPECT_LT(error.z(), 0.1);
  EXPECT_LT(error[depth], 3 * r.box.size_sigma[depth]) << error.transpose();
  // Not let through, it is refused, and the operator told why.
  LocateOptions never = LabOptions();
  never.min_open_depth_sigma = 0;
  const LocateResult refused = Locate(a.input, never);
  EXPECT_FALSE(refused.found);
  EXPECT_EQ(refused.reason, Failure::kFitFailed);
  EXPECT_TRUE(Contains(refused.detail, "the side shades flat, as a block's face seen square on"))
      << refused.detail;
  EXPECT_TRUE(Contains(refused.detail, "cannot tell a block from a pipe standing up"))
      << refused.detail;
}

// An object of a level (pipes unless told) with the thesis's cameras, asked for as the
// benchmark asks: the scene's objects before it located first, and those found known to the
// locator.
ObjectEvaluation AsTheBenchmarkAsks(uint64_t seed, const std::string& name,
                                    const LocateOptions& options,
                                    site::SiteLevel level = site::SiteLevel::kPipes) {
  const site::Scene scene = site::SiteScene(seed, level, false);
  for (const auto& e : EvaluateScene(scene, "thesis_" + std::to_string(seed), seed, options))
    if (e.object_name == name) return e;
  ADD_FAILURE() << name << " is not in the scene";
  return {};
}

TEST(SideShading, ANarrowBlocksFaceIsMeasuredInHalfPixelBins) {
  // Level far, seed 30, as the benchmark asks (the pipe it carries first): support_2, 76 in
  // away, seen square on. The upright pipe fitted against it is under 12 px across: in bins a
  // pixel wide its side was left unmeasured, and the block refused as a pipe standing there.
  // In half pixels the side shades flat, and the block is found, its depth left open.
  const auto support = [](bool half_pixel_bins) {
    LocateOptions options = SiteLocateOptions();
    options.side_half_pixel_bins = half_pixel_bins;
    return AsTheBenchmarkAsks(30, "support_2", options, site::SiteLevel::kFar);
  };
  const ObjectEvaluation found = support(true);
  ASSERT_GE(found.visible, kFullView);
  ASSERT_TRUE(found.result.found) << found.result.detail;
  EXPECT_FALSE(found.wrong) << found.size_error.transpose();
  const BoxResult& box = found.result.box;
  EXPECT_GE(std::max(box.size_sigma.x(), box.size_sigma.y()), LabOptions().min_open_depth_sigma);
  EXPECT_LT(std::abs(found.size_error.z()), 0.1);
  const ObjectEvaluation refused = support(false);
  EXPECT_FALSE(refused.result.found);
  EXPECT_TRUE(Contains(refused.result.detail, "a cylinder explains the outline about as well"))
      << refused.result.detail;
}

TEST(SideShading, ABlockSeenSquareOnWhoseFitClaimsItsDepthIsRefused) {
  // Level pipes, seed 21, as the benchmark asks (the pipes built first): support_5, 57 in away
  // under a pipe, seen square on, its side shading flat. Its fit gives its depth to 0.08 in,
  // from edges that are not the block's: let through, it came out 1.3 in too deep.
  const auto support = [](const LocateOptions& options) {
    return AsTheBenchmarkAsks(21, "support_5", options);
  };
  const ObjectEvaluation refused = support(SiteLocateOptions());
  ASSERT_GE(refused.visible, kFullView);
  EXPECT_FALSE(refused.result.found);
  EXPECT_TRUE(Contains(refused.result.detail, "the side shades flat, as a block's face seen"))
      << refused.result.detail;
  LocateOptions always = SiteLocateOptions();
  always.min_open_depth_sigma = 1e-6;
  const ObjectEvaluation through = support(always);
  ASSERT_TRUE(through.result.found) << through.result.detail;
  EXPECT_TRUE(through.wrong) << through.size_error.transpose() << " +/- "
                             << through.result.box.size_sigma.transpose();
}

TEST(SideShading, ABlockFarBetterWhereAnEdgeShouldShowIsNotHeldToTheWholeOutline) {
  // Level pipes, seed 13, as the benchmark asks: support_2, 54 in away under the pipe it
  // carries. The cylinder fitted to it leaves as much of its outline without an edge as the
  // block does (0.54 against 0.58 on the whole outline), but where an edge should show the
  // block scores 0.09 and the cylinder 0.27: found, its depth left open.
  const auto support = [](const LocateOptions& options) {
    return AsTheBenchmarkAsks(13, "support_2", options);
  };
  const LocateOptions options = SiteLocateOptions();
  const ObjectEvaluation found = support(options);
  ASSERT_GE(found.visible, kFullView);
  ASSERT_TRUE(found.result.found) << found.result.detail;
  EXPECT_FALSE(found.wrong) << found.size_error.transpose();
  EXPECT_GT(found.result.fit_score, options.box_over_cylinder * found.result.other_type_fit_score);
  EXPECT_LT(found.result.supported_fit_score, options.box_clearly_over_cylinder_supported *
                                                  found.result.other_type_supported_fit_score);
  // Held to the whole outline, it is refused.
  LocateOptions whole = options;
  whole.box_clearly_over_cylinder_supported = 0;
  const ObjectEvaluation refused = support(whole);
  EXPECT_FALSE(refused.result.found);
  EXPECT_TRUE(Contains(refused.result.detail, "a cylinder explains the outline about as well"))
      << refused.result.detail;
  LocateOptions over = options;
  over.box_clearly_over_cylinder_supported = 1.5;
  std::string why;
  EXPECT_FALSE(over.Check(&why));
  EXPECT_TRUE(Contains(why, "box_clearly_over_cylinder_supported")) << why;
}

// The block's model parameters (centre, size, yaw about the vertical).
Eigen::VectorXd BlockParams(const site::Box& b) {
  Eigen::VectorXd x(7);
  x << b.center, b.size, std::atan2(b.rotation(1, 0), b.rotation(0, 0));
  return x;
}

TEST(SideShading, ATurnedBlockFittedAsOneFaceIsTurnedToTheCreaseInItsShading) {
  // Level far, seed 30, the thesis's cameras: box_11, 93 in away, turned so that two faces
  // show, one lit and one dark. Fitted world-aligned first, it came out as one face 0.69 in too
  // wide and 1.48 in too shallow.
  const Asked a = AskFor(30, site::SiteLevel::kFar, false, "box_11", SolidType::kBox);
  ASSERT_NE(a.shape, nullptr);
  const auto& truth = std::get<site::Box>(*a.shape);
  const auto pair = PrepareImages(a.input);
  ASSERT_TRUE(pair.ok());
  const LocateOptions opt = LabOptions();
  const Eigen::Vector3d eye = a.input.left_camera.Center();
  // The shading steps where the block's nearest edge stands, in both images.
  const Eigen::VectorXd block = BlockParams(truth);
  const auto crease = FaceCrease(*pair, block, Views(a.input), opt);
  ASSERT_TRUE(crease.has_value());
  EXPECT_TRUE(EdgeAtCrease(block, *crease, eye, opt));
  // A block square on over the same extent has no edge there; the starts from it do.
  Eigen::VectorXd square_on = block;
  square_on[6] = 0;
  const auto at = FaceCrease(*pair, square_on, Views(a.input), opt);
  ASSERT_TRUE(at.has_value());
  const auto starts = CreaseStarts(square_on, *at, eye);
  ASSERT_EQ(starts.size(), kCreaseTurnsDeg.size());
  for (const auto& st : starts) {
    EXPECT_TRUE(EdgeAtCrease(st, *at, eye, opt)) << st.transpose();
    EXPECT_NEAR(st[5], block[5], 1e-9);
  }
  // Located: right, to a tenth of an inch in width and height.
  const LocateResult r = Locate(a.input, opt);
  ASSERT_TRUE(r.found) << r.detail;
  const Eigen::Vector3d error = SizeError(r.box, truth);
  EXPECT_LT(error.maxCoeff(), 0.25) << error.transpose();
  EXPECT_LT(error.z(), 0.1);
  // Without the crease, one face.
  LocateOptions no_crease = opt;
  no_crease.face_crease_gain = 0;
  const LocateResult one_face = Locate(a.input, no_crease);
  ASSERT_TRUE(one_face.found);
  EXPECT_GT(SizeError(one_face.box, truth).maxCoeff(), 0.5);
  LocateOptions bad = opt;
  bad.face_crease_agree = 0;
  ExpectCheckNames(bad, "face_crease_agree");
}

TEST(SideShading, APipeAskedForAsABoxIsRefusedWhenItsSideShadesClearlyRound) {
  // Level far, seed 8, 1920x1080: upright_1, 93 in away. A box fits its outline as well as a
  // cylinder on the outline that should show an edge, and better on the whole; its side
  // shades round hundreds of times better than flat.
  const Asked a = AskFor(8, site::SiteLevel::kFar, true, "upright_1", SolidType::kBox);
  ASSERT_NE(a.shape, nullptr);
  LocateOptions off;
  off.round_side_gain = 1e300;
  ExpectRefusedByTheRuleAlone(a.input, "shades round", off);
  // The bound is above the flat one, or a side would be both.
  off.round_side_gain = off.flat_side_gain / 2;
  ExpectCheckNames(off, "round_side_gain");
  // Asked for as what it is, it is found.
  Asked pipe = a;
  pipe.input.type = SolidType::kCylinder;
  EXPECT_TRUE(Locate(pipe.input).found);
}

TEST(SideShading, APipeWhoseSideShadesClearlyRoundIsHeldAgainstABoxWhereEdgesShouldShow) {
  // Level far, seed 3, 1920x1080: upright_2, 80 in away. A box scores better on the whole
  // outline, not on the part that should show an edge; the side shades round hundreds of times
  // better than flat.
  const Asked a = AskFor(3, site::SiteLevel::kFar, true, "upright_2", SolidType::kCylinder);
  ASSERT_NE(a.shape, nullptr);
  const auto& truth = std::get<site::Cylinder>(*a.shape);
  const LocateResult found = Locate(a.input);
  ASSERT_TRUE(found.found) << found.detail;
  EXPECT_NEAR(found.cylinder.radius, truth.radius, 0.03);
  EXPECT_NEAR(found.cylinder.height, truth.height, 0.15);
  EXPECT_LT((found.cylinder.center - truth.center).norm(), 0.1);
  EXPECT_GT(found.other_type_supported_fit_score, found.supported_fit_score);
  EXPECT_LT(found.other_type_fit_score, found.fit_score);
  // Its side not taken as clearly round, it is held against the box on the whole outline too,
  // but a box must beat it where an edge should show as well: it is still found. (Judged on
  // the whole outline alone, it was refused: "a box explains the outline much better".)
  LocateOptions off;
  off.round_side_gain = 1e300;
  const LocateResult unjudged = Locate(a.input, off);
  EXPECT_TRUE(unjudged.found) << unjudged.detail;
  EXPECT_LT(off.other_type_ratio * unjudged.other_type_fit_score, unjudged.fit_score);
}

}  // namespace
}  // namespace igms::object
