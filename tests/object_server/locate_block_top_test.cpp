// A block's top from where its sides' edges end (object_server/locate_steps.h: TopFromSides),
// and the locator lowering a block whose fit the pipe resting on it carried up: on rendered
// site scenes, with two lights and shadows.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <variant>

#include "common/sim/marks.h"
#include "common/sim/renderer.h"
#include "common/sim/site_scenes.h"
#include "object_server/locate_steps.h"

namespace igms::object {
namespace {

// A site scene's block, rendered, asked for as a box with the benchmark's marks
// (common/sim/vision/evaluation.h).
struct AskedBlock {
  site::Scene scene;
  LocateInput input;
  site::Box truth;
  bool present = false;
};
AskedBlock AskForBlock(uint64_t seed, site::SiteLevel level, const std::string& name) {
  AskedBlock a;
  a.scene = site::SiteScene(seed, level, false);
  const site::StereoImages images = site::RenderStereo(a.scene);
  for (size_t i = 0; i < a.scene.objects.size(); ++i) {
    const auto* box = std::get_if<site::Box>(&a.scene.objects[i].shape);
    if (a.scene.objects[i].name != name || !box) continue;
    a.truth = *box;
    a.present = true;
    a.input.marks = *site::GenerateMarks(*box, a.scene.cameras.left, seed * 1000 + i);
  }
  a.input.type = SolidType::kBox;
  a.input.left = images.left;
  a.input.right = images.right;
  a.input.left_camera = a.scene.cameras.left;
  a.input.right_camera = a.scene.cameras.right;
  return a;
}

// A site scene's pipe as the database would hold it (its true end-cap centres and radius).
KnownShape KnownPipe(const site::Scene& scene, const std::string& name) {
  KnownShape k{name, SolidType::kCylinder, Eigen::VectorXd(7), 0.02};
  for (const auto& o : scene.objects)
    if (const auto* c = std::get_if<site::Cylinder>(&o.shape); c && o.name == name)
      k.params << c->center - 0.5 * c->height * c->axis, c->center + 0.5 * c->height * c->axis,
          c->radius;
  return k;
}

// The box's fit parameters (centre, sizes along its own axes, yaw) with its top raised by
// `raise` world units.
Eigen::VectorXd Params(const site::Box& b, double raise) {
  Eigen::VectorXd x(7);
  x << b.center + Eigen::Vector3d(0, 0, 0.5 * raise), b.size + Eigen::Vector3d(0, 0, raise),
      std::atan2(b.rotation(1, 0), b.rotation(0, 0));
  return x;
}

// TopFromSides on the block's true footprint raised by `raise`, measuring the edges over
// the whole of both images.
std::optional<Eigen::VectorXd> Lowered(const AskedBlock& a, double raise) {
  const LocateOptions options;
  const auto pair = PrepareImages(a.input);
  EXPECT_TRUE(pair.ok());
  const Gradients left(pair->left, cv::Rect(0, 0, pair->left.cols, pair->left.rows),
                       options.edge_sigma);
  const Gradients right(pair->right, cv::Rect(0, 0, pair->right.cols, pair->right.rows),
                        options.edge_sigma);
  const std::array<FitView, 2> views = {FitView(&a.input.left_camera, &left),
                                        FitView(&a.input.right_camera, &right)};
  FitOutcome f;
  f.ok = true;
  f.params = Params(a.truth, raise);
  return TopFromSides(views, FitSettings(options, 0), options, f);
}

TEST(BlockTop, ABlocksSidesRunToItsTop) {
  // Level far, seed 5: box_6, a block in the open, face on.
  const AskedBlock a = AskForBlock(5, site::SiteLevel::kFar, "box_6");
  ASSERT_TRUE(a.present);
  EXPECT_FALSE(Lowered(a, 0.0).has_value());
  // Fitted 40% too tall, its sides stop where the block does.
  const auto lowered = Lowered(a, 0.4 * a.truth.size.z());
  ASSERT_TRUE(lowered.has_value());
  EXPECT_NEAR((*lowered)[5], a.truth.size.z(), 0.1 * a.truth.size.z());
  EXPECT_NEAR((*lowered)[2] - 0.5 * (*lowered)[5], a.truth.center.z() - 0.5 * a.truth.size.z(),
              1e-9);  // the bottom stays
}

TEST(BlockTop, ABlockUnderAPipeWhoseEndRisesAboveItIsFoundToItsTop) {
  // Level pipes, seed 10: support_3 carries a pipe that rises behind it to above its top. Its
  // fit takes the top up to the pipe's (0.54 in too tall, or refused); the sides' edges stop
  // at the block's.
  const AskedBlock a = AskForBlock(10, site::SiteLevel::kPipes, "support_3");
  ASSERT_TRUE(a.present);
  const LocateResult found = Locate(a.input);
  ASSERT_TRUE(found.found) << found.detail;
  EXPECT_NEAR(found.box.size.z(), a.truth.size.z(), 0.1);
  EXPECT_LT((found.box.center - a.truth.center).norm(), 0.2);
  // Without the sides' reach, the fit lowered by shares of its height finds it too; without
  // either, it is not found to its top.
  LocateOptions by_shares;
  by_shares.box_side_reach = 1e-9;
  const LocateResult lowered = Locate(a.input, by_shares);
  ASSERT_TRUE(lowered.found) << lowered.detail;
  EXPECT_NEAR(lowered.box.size.z(), a.truth.size.z(), 0.1);
  LocateOptions off = by_shares;
  off.lowered_shares.clear();
  const LocateResult up_to_the_pipe = Locate(a.input, off);
  EXPECT_FALSE(up_to_the_pipe.found &&
               std::abs(up_to_the_pipe.box.size.z() - a.truth.size.z()) < 0.1);
}

TEST(BlockTop, ABlockWhoseTopNothingHoldsBelowThePipeOnItSaysSo) {
  // Level pipes, seed 3: support_1 carries a tilted pipe across its top. Fitted up to the
  // pipe's top, the outline explains the edges poorly; fitted lower, the block explains them,
  // but nothing the fit measures holds its height (its top face lies under the pipe). The
  // refusal says both.
  const AskedBlock a = AskForBlock(3, site::SiteLevel::kPipes, "support_1");
  ASSERT_TRUE(a.present);
  const LocateResult r = Locate(a.input);
  ASSERT_FALSE(r.found);
  EXPECT_EQ(r.reason, Failure::kLeftRightInconsistent) << r.detail;
  EXPECT_NE(r.detail.find("explains the edges poorly"), std::string::npos) << r.detail;
  EXPECT_NE(r.detail.find("nothing there holds its height"), std::string::npos) << r.detail;
  // Without the lowered fits, only the first part is said.
  LocateOptions off;
  off.lowered_shares.clear();
  off.box_side_reach = 1e-9;
  const LocateResult plain = Locate(a.input, off);
  ASSERT_FALSE(plain.found);
  EXPECT_EQ(plain.detail.find("nothing there holds"), std::string::npos) << plain.detail;
}

TEST(BlockTop, ANarrowSupportReachesUpToTheKnownPipeOverItsMiddle) {
  // Level clutter, seed 6: support_13, a narrow block of about the table's shade seen square
  // on, carries lying_12, which the database holds. Its fit is thin, its depth and height left
  // open, its centre 0.5 in from the pipe's axis, beyond its half diagonal (0.2 in) but within
  // two of its centre's deviations: it reaches up to the pipe's underside.
  AskedBlock a = AskForBlock(6, site::SiteLevel::kClutter, "support_13");
  ASSERT_TRUE(a.present);
  a.input.known.push_back(KnownPipe(a.scene, "lying_12"));
  const LocateResult r = Locate(a.input);
  ASSERT_TRUE(r.found) << r.detail;
  EXPECT_NEAR(r.box.size.z(), a.truth.size.z(), 0.1);
  EXPECT_LT(std::abs(r.box.center.z() - a.truth.center.z()), 0.1);
  // Held to its half diagonal, the pipe passes beside it and the height stays open: the pass
  // that fitted it is refused, and the first refusal stands (its foot left empty).
  LocateOptions footprint;
  footprint.known_reach_sigmas = 0;
  const LocateResult open = Locate(a.input, footprint);
  ASSERT_FALSE(open.found);
  EXPECT_NE(open.detail.find("empty on its bottom"), std::string::npos) << open.detail;
  std::string error;
  footprint.known_reach_sigmas = -1;
  EXPECT_FALSE(footprint.Check(&error));
  EXPECT_NE(error.find("known_reach_sigmas"), std::string::npos) << error;
}

TEST(BlockTop, TheLoweredSharesAreChecked) {
  std::string error;
  for (const double bad : {0.0, 1.0, -0.5, std::nan("")}) {
    LocateOptions options;
    options.lowered_shares = {0.5, bad};
    EXPECT_FALSE(options.Check(&error)) << bad;
    EXPECT_NE(error.find("lowered_shares"), std::string::npos);
  }
  LocateOptions none;
  none.lowered_shares.clear();
  EXPECT_TRUE(none.Check(&error)) << error;
}

}  // namespace
}  // namespace igms::object
