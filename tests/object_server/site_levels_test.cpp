// A seeded subset of the site benchmark (bench_site_accuracy): two scenes of each level with
// the thesis's cameras (pipes in any direction and on supports, clutter with occlusion and
// textures, far objects under noise; two lights and shadows), asserting that the objects in
// full view are found right, few wrong models are reported, and marks around bare table or a gap
// are refused. The bounds hold the present figures (19 of 30 in full view found right, no wrong
// model of 38 objects, no bare or gap request found, 1 wrong type found) against regression.
// Before the fit's score was bounded (max_fit_score) and a box had to beat a cylinder
// (box_over_cylinder), 17 were found right but 15 wrong models and 18 wrong types were reported;
// with the bound in pixels (1.0) rather than in the reference camera's (0.9), 3 wrong models.
// The targets (99% found, wrong models rare, wrong types refused) are not met yet:
// bench_site_accuracy prints how far off.
#include <gtest/gtest.h>

#include <limits>
#include <opencv2/core/utility.hpp>
#include <string>

#include "common/sim/site_scenes.h"
#include "common/sim/vision/evaluation.h"

namespace igms::object {
namespace {

TEST(SiteLevels, SeededScenesOfEachLevel) {
  cv::setNumThreads(1);
  std::vector<ObjectEvaluation> all;
  std::vector<NothingThereEvaluation> nothing;
  for (const auto level :
       {site::SiteLevel::kPipes, site::SiteLevel::kClutter, site::SiteLevel::kFar}) {
    for (int seed = 900; seed < 902; ++seed) {
      const auto scene = site::SiteScene(seed, level, false);
      const std::string name = std::string(site::SiteLevelName(level)) + "_" + std::to_string(seed);
      const auto evals = EvaluateScene(scene, name, seed);
      all.insert(all.end(), evals.begin(), evals.end());
      const auto n = EvaluateNothingThere(scene, name, seed, 1);
      nothing.insert(nothing.end(), n.begin(), n.end());
    }
  }
  const Summary s = Summarize(all, "");
  std::printf("in full view %d of %d found, %d wrong; partly hidden %d: %d refused, %d wrong\n",
              s.full_found, s.full, s.full_wrong, s.hidden, s.hidden_refused, s.hidden_wrong);
  for (const auto& e : all)
    if (e.visible >= kFullView && (!e.result.found || e.wrong))
      std::printf("  %s %s (%s, visible %.2f): %s %s\n", e.scene_name.c_str(),
                  e.object_name.c_str(), e.kind.c_str(), e.visible,
                  e.wrong ? "WRONG" : FailureName(e.result.reason), e.result.detail.c_str());
  int false_finds = 0, wrong_types = 0, requests = 0;
  for (const auto& n : nothing) {
    if (n.what == "wrong_type") {
      wrong_types += n.result.found;
      continue;
    }
    ++requests;
    false_finds += n.result.found;
    if (n.result.found)
      std::printf("  %s: nothing there (%s) found\n", n.scene_name.c_str(), n.what.c_str());
  }
  std::printf("nothing there: %d of %d found; wrong types found: %d\n", false_finds, requests,
              wrong_types);
  ASSERT_GE(s.full, 25);
  // Found and right: a wrong model counts against, not for.
  EXPECT_GE(s.full_found - s.full_wrong, 19);
  EXPECT_LE(s.full_wrong + s.hidden_wrong, 3);
  ASSERT_GE(requests, 5);
  EXPECT_EQ(false_finds, 0);
  // 2 of about 30 since a pipe's side is judged by its shading and the other type is fitted
  // as if asked for (6 before).
  EXPECT_LE(wrong_types, 3);
}

// A found block is a wrong model when a size is off by more than 0.5 in and by more than 3 of
// its reported sigma: a block seen square on whose depth the result says is ill seen is not.
TEST(SiteLevels, ABlocksSizeIsWrongOnlyBeyondItsSigma) {
  ObjectEvaluation e;
  e.kind = "box";
  e.result.found = true;
  e.position_error = 0.3;
  e.result.box.size_sigma = {0.05, 0.6, 0.05};
  e.size_error = {0.02, 1.5, 0.03};
  EXPECT_FALSE(WrongModel(e));  // depth 1.5 in off, within 2.5 sigma
  e.size_error = {0.02, 1.9, 0.03};
  EXPECT_TRUE(WrongModel(e));  // beyond 3 sigma
  e.size_error = {0.6, 0.1, 0.03};
  EXPECT_TRUE(WrongModel(e));  // the width, which the face shows, off by 0.6 in
  e.size_error = {0.02, 0.4, 0.03};
  e.result.box.size_sigma = {0.05, 0.05, 0.05};
  EXPECT_FALSE(WrongModel(e));  // within 0.5 in: never wrong, whatever its sigma
  e.position_error = 1.2;
  EXPECT_TRUE(WrongModel(e));  // the centre more than 1 in off
  EXPECT_TRUE(OffBeyondSigma(0.6, 0.1));
  EXPECT_FALSE(OffBeyondSigma(0.6, 0.3));
  EXPECT_FALSE(OffBeyondSigma(0.4, 0.01));
}

// A thin upright pipe (radius 0.25 in, 5.5 in tall, 46 in away, 1920x1080) whose lower half
// stands against the table: a box fits its upper half, against the black above the table's
// horizon, better than the whole pipe fits, but leaves the marks' bottom empty; it must not
// refuse the pipe. (Nothing holds the pipe's foot against the table, so its length is left
// open, +/- 100 in, and that refuses it: the reason must be its length, not the box.)
TEST(SiteLevels, ABoxOnAPipesUpperHalfDoesNotRefuseThePipe) {
  cv::setNumThreads(1);
  const auto scene = site::SiteScene(6, site::SiteLevel::kClutter, true);
  const auto evals = EvaluateScene(scene, "clutter_hd_6", 6);
  const ObjectEvaluation* pipe = nullptr;
  for (const auto& e : evals)
    if (e.object_name == "upright_0") pipe = &e;
  ASSERT_NE(pipe, nullptr);
  ASSERT_GE(pipe->visible, kFullView);
  EXPECT_FALSE(pipe->wrong);
  EXPECT_EQ(pipe->result.detail.find("a box"), std::string::npos) << pipe->result.detail;
  if (!pipe->result.found) {
    EXPECT_NE(pipe->result.detail.find("do not determine the cylinder's length"), std::string::npos)
        << pipe->result.detail;
  }
}

// A block under a pipe (86 in away, 1920x1080): with the pipe built first, its edges are not
// taken for the block's, and the block is found right. Without it the block was refused while
// the cylinder tried against it was fitted less fully than a cylinder asked for; now it is
// found right too. Never a wrong model.
TEST(SiteLevels, APipeBuiltFirstLetsTheBlockItRestsOnBeFound) {
  cv::setNumThreads(1);
  const auto scene = site::SiteScene(5000, site::SiteLevel::kFar, true);
  for (const bool database : {false, true}) {
    const auto evals = EvaluateScene(scene, "far_hd_5000", 5000, {}, "", database);
    const ObjectEvaluation* block = nullptr;
    for (const auto& e : evals)
      if (e.object_name == "support_5") block = &e;
    ASSERT_NE(block, nullptr);
    ASSERT_GE(block->visible, kFullView);
    EXPECT_FALSE(block->wrong);
    if (database) {
      EXPECT_TRUE(block->result.found) << block->result.detail;
    }
  }
}

// A pipe raised on two blocks (78 in away, 1920x1080) whose lower limb, shaded, shows no strong
// edge: the boundary holds its upper limb and the blocks' sides down to the table, and the
// rectangle around it all starts a fat upright cylinder, which fits poorly. The starts from its
// upper limb alone (the limb line nearest the top), tried then, find the pipe, and with the
// pipe built, both blocks under it; before them, all three were refused.
TEST(SiteLevels, APipeOnBlocksIsFoundFromItsUpperLimb) {
  cv::setNumThreads(1);
  const auto scene = site::SiteScene(10, site::SiteLevel::kPipes, true);
  const auto evals = EvaluateScene(scene, "pipes_hd_10", 10);
  int checked = 0;
  for (const auto& e : evals) {
    if (e.object_name != "lying_0" && e.object_name != "support_1" && e.object_name != "support_2")
      continue;
    ++checked;
    ASSERT_GE(e.visible, kFullView) << e.object_name;
    EXPECT_TRUE(e.result.found) << e.object_name << ": " << e.result.detail;
    EXPECT_FALSE(e.wrong) << e.object_name;
    if (e.object_name == "lying_0") {
      EXPECT_LT(e.radius_error, 0.03);
      EXPECT_LT(e.height_error, 0.1);
    }
  }
  EXPECT_EQ(checked, 3);
}

// The evaluation of the object named, which must be in the scene once and in full view.
const ObjectEvaluation* InFullView(const std::vector<ObjectEvaluation>& evals,
                                   const std::string& name) {
  const ObjectEvaluation* found = nullptr;
  for (const auto& e : evals)
    if (e.object_name == name) {
      EXPECT_EQ(found, nullptr) << name << " twice";
      found = &e;
    }
  EXPECT_NE(found, nullptr) << name;
  if (found) {
    EXPECT_GE(found->visible, kFullView) << name;
  }
  return found;
}

// Found, not a wrong model, and within the accuracy on every level: a pipe's radius to
// 0.03 in and its length to 0.1 in, a block's sizes to 0.1 in, the position to 0.3 in.
void ExpectFoundRight(const ObjectEvaluation* e) {
  ASSERT_NE(e, nullptr);
  ASSERT_TRUE(e->result.found) << e->object_name << ": " << e->result.detail;
  EXPECT_FALSE(e->wrong) << e->object_name;
  if (e->kind == "box") {
    EXPECT_LT(e->size_error.maxCoeff(), 0.1) << e->object_name;
  } else {
    EXPECT_LT(e->radius_error, 0.03) << e->object_name;
    EXPECT_LT(e->height_error, 0.1) << e->object_name;
  }
  EXPECT_LT(e->position_error, 0.3) << e->object_name;
}

// A pipe tilted onto a block that stands in front of part of its lower limb (70 in away,
// 1920x1080): the block's sides are most of the boundary, and the rectangle around it all
// starts a cylinder far too fat. Its limb pixels (the boundary's dominant orientation), however
// few of the boundary they are, split into the upper limb line and the lower one, and the two
// lines alone start the pipe; before, it was refused as explaining the edges poorly.
TEST(SiteLevels, APipeWhoseBlockHidesPartOfItsLowerLimbStartsFromBothLimbLines) {
  cv::setNumThreads(1);
  const auto evals =
      EvaluateScene(site::SiteScene(5003, site::SiteLevel::kPipes, true), "pipes_hd_5003", 5003);
  ExpectFoundRight(InFullView(evals, "lying_2"));
}

// A block (39 in away, the thesis's cameras) carrying the end of a pipe that the locator
// refused: the pipe's limb carries one of the block's vertical edges on up past its top, and
// every start from the boundary took the pipe in. The start from the boundary between the
// block's outermost vertical edges and no higher than the lower of their tops finds it; before,
// it was refused as explaining the edges poorly.
TEST(SiteLevels, ABlockUnderAnUnknownPipeStartsBelowItsSidesTops) {
  cv::setNumThreads(1);
  const auto evals = EvaluateScene(site::SiteScene(5006, site::SiteLevel::kClutter, false),
                                   "clutter_thesis_5006", 5006);
  const ObjectEvaluation* pipe = InFullView(evals, "lying_0");  // the pipe it carries
  ASSERT_NE(pipe, nullptr);
  EXPECT_FALSE(pipe->result.found);
  ExpectFoundRight(InFullView(evals, "support_2"));
}

// A block (39 in away, the thesis's cameras) carrying the high end of a tilted pipe whose end
// rises over it, the pipe refused: every fit took the pipe's end in, 1.2 in too tall, and
// explained the edges poorly; its sides' edges run on up into the pipe's and say nothing of its
// top. Fitted again lowered to shares of its height, it is found.
TEST(SiteLevels, ABlockFittedUpToThePipeOnItIsFittedAgainLowered) {
  cv::setNumThreads(1);
  const auto evals =
      EvaluateScene(site::SiteScene(4, site::SiteLevel::kPipes, false), "pipes_thesis_4", 4);
  for (const auto& e : evals) {
    if (e.object_name == "lying_2") {
      EXPECT_FALSE(e.result.found) << "the pipe it carries";
    }
  }
  ExpectFoundRight(InFullView(evals, "support_3"));
}

// A thin upright pipe in clutter (47 in away, the thesis's cameras) whose foot nothing holds: the
// fit ends it 2 in above the table and leaves the marks' bottom empty. With the site's floor
// known (the lab's floor_height, the table top) it is fitted again standing on it, and found;
// without, it is refused.
TEST(SiteLevels, AnUprightPipeWhoseFootIsUnseenStandsOnTheFloor) {
  cv::setNumThreads(1);
  const auto scene = site::SiteScene(3, site::SiteLevel::kClutter, false);
  ExpectFoundRight(InFullView(EvaluateScene(scene, "clutter_thesis_3", 3), "upright_5"));
  const auto without = EvaluateScene(scene, "clutter_thesis_3", 3, LocateOptions{});
  const ObjectEvaluation* e = InFullView(without, "upright_5");
  ASSERT_NE(e, nullptr);
  EXPECT_FALSE(e->result.found && !e->wrong);
}

// A support in clutter (51 in away, the thesis's cameras) whose lower half stands against the
// table, in nearly its shade: the fit takes its upper part alone and leaves the marks' bottom
// empty. With the site's floor known it is fitted again standing on it, and found; without, it
// is refused (on the first pass alone: the second, with a lower bar for its edges, finds its
// foot; the third, at the image's noise, is turned off with it).
TEST(SiteLevels, ABlockWhoseFootHasTheTablesShadeStandsOnTheFloor) {
  cv::setNumThreads(1);
  const auto scene = site::SiteScene(5001, site::SiteLevel::kClutter, false);
  ExpectFoundRight(InFullView(EvaluateScene(scene, "clutter_thesis_5001", 5001), "support_7"));
  LocateOptions no_floor = SiteLocateOptions();
  no_floor.floor_height.reset();
  ExpectFoundRight(
      InFullView(EvaluateScene(scene, "clutter_thesis_5001", 5001, no_floor), "support_7"));
  no_floor.retry_edge_quantile = 0;
  no_floor.retry_noise_gradient = 0;
  const auto without = EvaluateScene(scene, "clutter_thesis_5001", 5001, no_floor);
  const ObjectEvaluation* e = InFullView(without, "support_7");
  ASSERT_NE(e, nullptr);
  EXPECT_FALSE(e->result.found);
  EXPECT_NE(e->result.detail.find("empty on its bottom"), std::string::npos) << e->result.detail;
}

// A thin upright pipe in clutter (64 in away, 1920x1080) whose matched patch is mostly the
// objects beside it, at other depths: the whole patch correlates 0.38 with the right image,
// under min_match_zncc. Matched again on the band along its boundary alone, it is found.
TEST(SiteLevels, AThinPipeAmongOthersIsMatchedOnItsOwnEdges) {
  cv::setNumThreads(1);
  const auto scene = site::SiteScene(5007, site::SiteLevel::kClutter, true);
  ExpectFoundRight(InFullView(EvaluateScene(scene, "clutter_hd_5007", 5007), "upright_1"));
  LocateOptions whole_patch = SiteLocateOptions();
  whole_patch.match_band_px = 0;
  const auto without = EvaluateScene(scene, "clutter_hd_5007", 5007, whole_patch);
  const ObjectEvaluation* e = InFullView(without, "upright_1");
  ASSERT_NE(e, nullptr);
  EXPECT_FALSE(e->result.found);
  EXPECT_EQ(e->result.reason, Failure::kMatchOverThreshold) << e->result.detail;
  whole_patch.match_band_px = -1;
  std::string error;
  EXPECT_FALSE(whole_patch.Check(&error));
  EXPECT_NE(error.find("match_band_px"), std::string::npos) << error;
}

TEST(SiteLevels, TheFloorIsChecked) {
  std::string error;
  EXPECT_TRUE(SiteLocateOptions().Check(&error)) << error;
  LocateOptions options;
  options.floor_height = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(options.Check(&error));
  EXPECT_NE(error.find("floor_height"), std::string::npos);
  options = SiteLocateOptions();
  options.floor_gap = -0.1;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_NE(error.find("floor_gap"), std::string::npos);
  options = SiteLocateOptions();
  options.max_limb_shading_px = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(options.Check(&error));
  EXPECT_NE(error.find("max_limb_shading_px"), std::string::npos);
}

}  // namespace
}  // namespace igms::object
