// A seeded subset of the accuracy benchmark: 20 generated testbed scenes (upright and lying
// cylinders, a block, 3-7 ft, default noise and blur, operator marks as modelled), asserting
// the project's targets so accuracy cannot silently regress.
#include <gtest/gtest.h>

#include <opencv2/core/utility.hpp>

#include "common/sim/testbed.h"
#include "common/sim/vision/evaluation.h"

namespace igms::object {
namespace {

TEST(Accuracy, TwentySeededScenesMeetTheTargets) {
  std::vector<ObjectEvaluation> all;
  for (int seed = 500; seed < 520; ++seed) {
    const auto scene = site::RandomTestbedScene(seed);
    const auto evals = EvaluateScene(scene, "scene_" + std::to_string(seed), seed);
    all.insert(all.end(), evals.begin(), evals.end());
  }
  std::vector<ObjectEvaluation> cylinders;
  for (const auto& e : all)
    if (e.kind != "box") cylinders.push_back(e);
  const Summary c = Summarize(cylinders, "");
  const Summary b = Summarize(all, "box");
  const Summary every = Summarize(all, "");
  const Summary lying = Summarize(all, "lying");
  std::printf(
      "cylinders n=%d found %.1f%%: radius median %.4f, height median %.4f, position median %.3f\n",
      c.count, 100 * c.found_rate, c.radius_median, c.height_median, c.position_median);
  std::printf("boxes n=%d found %.1f%%: size median %.3f %.3f %.3f, position median %.3f\n",
              b.count, 100 * b.found_rate, b.size_median.x(), b.size_median.y(), b.size_median.z(),
              b.position_median);
  ASSERT_GE(c.count, 50);
  ASSERT_GE(b.count, 15);
  EXPECT_GT(every.found_rate, 0.95);
  EXPECT_LT(c.radius_median, 0.03);
  EXPECT_LT(c.height_median, 0.03);
  EXPECT_LT(c.position_median, 0.3);
  // A pipe lying on the table: its length rests on the turn of its axis in depth, read from
  // its ends' disparity and its seen cap; with the blur correction of curved edges the
  // median is under the target (0.018 in over 100 scenes).
  std::printf("lying cylinders n=%d found %.1f%%: height median %.4f\n", lying.count,
              100 * lying.found_rate, lying.height_median);
  EXPECT_GT(lying.found_rate, 0.95);
  EXPECT_LT(lying.radius_median, 0.03);
  EXPECT_LT(lying.height_median, 0.03);
  EXPECT_GT(b.found_rate, 0.95);
  EXPECT_LT(b.position_median, 0.3);
  // A block's size along the view rests on the edges between the faces the cameras see
  // (front and side, front and top): with them it meets the target too. Half the blocks are
  // turned; sizes are along each block's own axes.
  EXPECT_LT(b.size_median.x(), 0.1);
  EXPECT_LT(b.size_median.y(), 0.1);
  EXPECT_LT(b.size_median.z(), 0.1);
  EXPECT_LT(b.axis_median_deg, 2.0);
  // The reported uncertainties can be believed: most errors lie within two of them (about
  // 95% over 100 scenes; the bound leaves room for 20 scenes' scatter).
  std::printf("errors within 2 sigma: cylinders %.0f%%, boxes %.0f%%\n", 100 * c.within_2_sigma,
              100 * b.within_2_sigma);
  EXPECT_GT(c.within_2_sigma, 0.8);
  EXPECT_GT(b.within_2_sigma, 0.8);
}

// Blocks turned about the vertical (up to 40 degrees either way): the locator tries a turned
// box when the world-aligned one misses the edges, and reports its yaw and its size along
// its own axes. Today 22 of 24 are found; the two others are refused for a depth the images
// leave open (they would be wrong by 1.5 and 2.2 in), and one found block's depth is wrong.
TEST(Accuracy, TurnedBlocksAreFoundWithTheirYaw) {
  site::RandomSceneOptions options;
  options.upright_cylinders = 0;
  options.lying_cylinders = 0;
  options.boxes = 2;
  options.turned_box_share = 1.0;
  std::vector<ObjectEvaluation> all;
  for (int seed = 700; seed < 712; ++seed) {
    const auto scene = site::RandomTestbedScene(seed, options);
    const auto evals = EvaluateScene(scene, "scene_" + std::to_string(seed), seed);
    all.insert(all.end(), evals.begin(), evals.end());
  }
  const Summary b = Summarize(all, "box");
  int within_3deg = 0;
  for (const auto& e : all) within_3deg += e.result.found && e.axis_error_deg < 3.0;
  std::printf(
      "turned boxes n=%d found %.1f%%: size median %.3f %.3f %.3f, position median %.3f, yaw "
      "error median %.2f deg, %d within 3 deg\n",
      b.count, 100 * b.found_rate, b.size_median.x(), b.size_median.y(), b.size_median.z(),
      b.position_median, b.axis_median_deg, within_3deg);
  // A block seen so that its depth is left open is refused rather than guessed (a correct
  // refusal, not a miss); a wrong model is the failure that counts.
  int wrong = 0;
  for (const auto& e : all) {
    wrong += e.wrong;
    if (!e.result.found || e.wrong)
      std::printf("  %s %s: %s %s\n", e.scene_name.c_str(), e.object_name.c_str(),
                  e.wrong ? "WRONG" : FailureName(e.result.reason), e.result.detail.c_str());
    if (!e.result.found) {
      EXPECT_NE(e.result.detail.find("do not determine"), std::string::npos) << e.result.detail;
    }
  }
  ASSERT_GE(b.count, 20);
  EXPECT_GE(b.found_rate, 0.9);
  EXPECT_LE(wrong, 1);
  EXPECT_LT(b.position_median, 0.3);
  EXPECT_LT(b.size_median.maxCoeff(), 0.1);
  EXPECT_LT(b.axis_median_deg, 2.0);
  EXPECT_GE(within_3deg, 0.7 * b.count);
}

}  // namespace
}  // namespace igms::object
