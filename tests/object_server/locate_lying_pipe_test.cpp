// Lying pipes: one whose far limb shows no edge, one lying on a block, and the block under a
// pipe's end, where the two merge into one outline. The locator on rendered site scenes, with
// two lights and shadows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>

#include "tests/object_server/site_request.h"

namespace igms::object {
namespace {

// The request's pipe located with the default options: found, its radius, length and centre
// within the accuracy targets.
LocateResult ExpectPipeFoundRight(const SiteRequest& r) {
  const auto& truth = std::get<site::Cylinder>(r.shape);
  LocateResult found = Locate(r.input);
  EXPECT_TRUE(found.found) << found.detail;
  if (!found.found) return found;
  EXPECT_NEAR(found.cylinder.radius, truth.radius, 0.03);
  EXPECT_NEAR(found.cylinder.height, truth.height, 0.1);
  EXPECT_LT((found.cylinder.center - truth.center).norm(), 0.1);
  return found;
}

TEST(LyingPipe, APipeWhoseOutlinePartlyShowsNoEdgeIsJudgedWhereItShouldShowOne) {
  // Level clutter, seed 5: lying_9, in full view, its outline against a background of its own
  // shade in part. The right fit scores 0.98 (the bound is 0.9), and 0.46 on the outline that
  // should show an edge.
  const SiteRequest r = AskFor(5, site::SiteLevel::kClutter, false, "lying_9");
  ASSERT_TRUE(r.present);
  const LocateResult found = ExpectPipeFoundRight(r);
  const LocateOptions options;
  EXPECT_GT(found.fit_score, options.max_fit_score);
  EXPECT_LE(found.supported_fit_score, options.max_lying_supported_score);
  // Held to the bound of every other fit, it is refused.
  LocateOptions bound;
  bound.max_lying_fit_score = bound.max_fit_score;
  const LocateResult refused = Locate(r.input, bound);
  EXPECT_FALSE(refused.found);
  EXPECT_EQ(refused.reason, Failure::kLeftRightInconsistent) << refused.detail;
}

TEST(LyingPipe, APipeLyingOnABlockIsFoundFromTheUpperPartOfTheOutline) {
  // Level pipes, seed 5: lying_1 rests on its supports, turned towards the cameras; the
  // marks and the boundary take in the block under it, and the fit from the whole boundary
  // is a fat pipe over both (refused, score 1.63).
  const SiteRequest r = AskFor(5, site::SiteLevel::kPipes, false, "lying_1");
  ASSERT_TRUE(r.present);
  const auto& truth = std::get<site::Cylinder>(r.shape);
  ExpectPipeFoundRight(r);
  // The raised pipe's fits all refused (only an exactly level axis kept): what is left fits
  // the pipe and the block as one, and is refused.
  LocateOptions no_raised;
  no_raised.raised_pipe_max_tilt_deg = 0;
  const LocateResult merged = Locate(r.input, no_raised);
  EXPECT_NE(merged.reason, Failure::kBadInput) << merged.detail;
  EXPECT_FALSE(merged.found && std::abs(merged.cylinder.radius - truth.radius) < 0.03);
}

TEST(LyingPipe, ItsBoundsAreChecked) {
  std::string error;
  EXPECT_TRUE(LocateOptions{}.Check(&error)) << error;
  for (const double bad : {-1.0, 91.0, std::nan("")}) {
    LocateOptions options;
    options.raised_pipe_max_tilt_deg = bad;
    EXPECT_FALSE(options.Check(&error)) << bad;
    EXPECT_NE(error.find("raised_pipe_max_tilt_deg"), std::string::npos);
  }
  LocateOptions under;  // a lying pipe's bound under every other fit's
  under.max_lying_fit_score = under.max_fit_score - 0.1;
  EXPECT_FALSE(under.Check(&error));
  EXPECT_NE(error.find("max_lying_fit_score"), std::string::npos);
  LocateOptions negative;
  negative.max_lying_supported_score = -0.1;
  EXPECT_FALSE(negative.Check(&error));
}

TEST(LyingPipe, ABlockUnderAPipesEndIsStartedTurnedBetweenItsVerticalEdges) {
  // Level pipes, seed 4: support_1, turned 28 degrees from the world's axes, carries the end
  // of a pipe pointing at the cameras, whose round end widens the block's boundary to one
  // side. The boundary's edges give a yaw of 10 degrees, from which no fit reaches the block.
  const SiteRequest r = AskFor(4, site::SiteLevel::kPipes, false, "support_1");
  ASSERT_TRUE(r.present);
  const auto& truth = std::get<site::Box>(r.shape);
  const LocateResult found = Locate(r.input);
  ASSERT_TRUE(found.found) << found.detail;
  const auto sorted = [](const Eigen::Vector3d& s) {
    return std::make_pair(std::min(s.x(), s.y()), std::max(s.x(), s.y()));
  };
  EXPECT_NEAR(sorted(found.box.size).first, sorted(truth.size).first, 0.1);
  EXPECT_NEAR(sorted(found.box.size).second, sorted(truth.size).second, 0.25);
  EXPECT_NEAR(found.box.size.z(), truth.size.z(), 0.1);
  EXPECT_LT((found.box.center - truth.center).norm(), 0.3);
}

}  // namespace
}  // namespace igms::object
