// A pipe's limbs read inside its silhouette where its side shades up to them
// (object_server/locate_steps.h: LimbProfiles, LimbEdgeShift, RefineLimbsForShading): on
// profiles made from the model with a known edge, and on rendered scenes, whose upright pipes
// came out about a tenth of a pixel thin at each limb before.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "object_server/locate_steps.h"
#include "tests/object_server/testbed_twice.h"

namespace igms::object {
namespace {

// A limb's profile, its true edge at offset 0: a Lambertian side (constant a, cosine b and
// sine c of the angle round the axis) inside, `background` outside, blurred by `sigma`
// pixels; the edge search said to have found it at `peak`.
LimbProfile ShadedLimb(double a, double b, double c, double background, double sigma, double peak) {
  LimbProfile limb;
  limb.r_px = 6;
  limb.inside = 6;
  limb.outside = 4;
  limb.peak = peak;
  const auto shade = [&](double x) {
    if (x >= 0) return background;
    const double sine = std::max(-1.0, 1 + x / limb.r_px);
    return a + b * std::sqrt(1 - sine * sine) + c * sine;
  };
  for (double d = -limb.inside; d <= limb.outside + 1e-9; d += 0.25) {
    double sum = 0, weights = 0;
    for (double x = -12; x <= 12; x += 0.01) {
      const double w = std::exp(-0.5 * x * x / (sigma * sigma));
      sum += w * shade(d - x);
      weights += w;
    }
    limb.grey.push_back(sum / weights);
  }
  return limb;
}

TEST(LimbEdgeShift, PlacesAShadedLimbsEdgeOutsideWhereTheSearchFoundIt) {
  // A side darkening from 160 to 90 grey levels at its limb, against a background of 10: the
  // search found the edge 0.15 px inside.
  const std::vector<LimbProfile> limbs = {ShadedLimb(90, 70, 0, 10, 0.7, -0.15),
                                          ShadedLimb(100, 60, -5, 12, 0.7, -0.12)};
  const auto shift = LimbEdgeShift(limbs, 8.0);
  ASSERT_TRUE(shift.has_value());
  // The mean of what each limb's search missed by, to the fit's 0.05 px grid.
  EXPECT_NEAR(*shift, 0.135, 0.06);
}

TEST(LimbEdgeShift, LeavesAnEvenlyShadedSidesEdgeWhereItIs) {
  const std::vector<LimbProfile> limbs = {ShadedLimb(150, 0, 0, 20, 0.9, 0.0)};
  const auto shift = LimbEdgeShift(limbs, 8.0);
  ASSERT_TRUE(shift.has_value());
  EXPECT_NEAR(*shift, 0.0, 0.06);
}

TEST(LimbEdgeShift, RefusesALimbWithoutAClearStep) {
  // The side's shade at its limb 5 grey levels from the background, under the 8 asked for.
  EXPECT_FALSE(LimbEdgeShift({ShadedLimb(25, 10, 0, 20, 0.7, 0.0)}, 8.0).has_value());
  EXPECT_FALSE(LimbEdgeShift({}, 8.0).has_value());
  // A shadow's edge 2 px beyond the limb: no single step explains the profile.
  LimbProfile shadowed = ShadedLimb(90, 70, 0, 10, 0.7, 0.0);
  for (size_t k = 0; k < shadowed.grey.size(); ++k)
    if (-shadowed.inside + 0.25 * static_cast<double>(k) >= 2.0) shadowed.grey[k] += 40;
  EXPECT_FALSE(LimbEdgeShift({shadowed}, 8.0).has_value());
}

// The upright pipes of the easy testbed scenes, located with and without the limbs moved.
TEST(RefineLimbsForShading, UprightPipesComeOutTheirTrueRadius) {
  LocateOptions moved = SiteLocateOptions(), kept = moved;
  kept.max_limb_shading_px = 0;
  int uprights = 0, moved_count = 0;
  double off_before = 0, off_after = 0, thin_before = 0;
  for (const auto& [what, before, after] : EvaluateTestbedTwice(1000, 1003, kept, moved)) {
    if (after.object_name.rfind("upright", 0) != 0) continue;
    ASSERT_TRUE(before.result.found && after.result.found) << what;
    ++uprights;
    off_before += std::abs(before.radius_signed);
    off_after += std::abs(after.radius_signed);
    thin_before += before.radius_signed;
    // Only the radius moves: the axis and the sigmas are the first fit's.
    EXPECT_EQ(before.result.cylinder.center, after.result.cylinder.center) << what;
    EXPECT_EQ(before.result.cylinder.height, after.result.cylinder.height) << what;
    EXPECT_EQ(before.result.cylinder.radius_sigma, after.result.cylinder.radius_sigma);
    if (after.radius_signed == before.radius_signed) continue;  // a limb not measured
    ++moved_count;
    EXPECT_LT(std::abs(after.radius_signed), 0.006) << what;
  }
  ASSERT_GE(uprights, 6);
  EXPECT_GE(moved_count, 4);
  // Before: every one too thin, by about 0.01 in (a tenth of a pixel at each limb); after,
  // under half as far off on the whole.
  EXPECT_LT(thin_before / uprights, -0.006);
  EXPECT_LT(off_after, 0.5 * off_before);
}

}  // namespace
}  // namespace igms::object
