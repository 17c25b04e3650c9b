// A site scene's object asked for as its own type with the marks the accuracy benchmark gives
// it (common/sim/vision/evaluation.h): the request the locator's tests on rendered site scenes
// start from.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <variant>

#include "common/sim/marks.h"
#include "common/sim/renderer.h"
#include "common/sim/site_scenes.h"
#include "object_server/locate.h"

namespace igms::object {

struct SiteRequest {
  site::Scene scene;
  LocateInput input;
  site::Shape shape;     // the object's truth
  bool present = false;  // the scene holds an object of that name
};

inline SiteRequest AskFor(uint64_t seed, site::SiteLevel level, bool hd, const std::string& name) {
  SiteRequest r;
  r.scene = site::SiteScene(seed, level, hd);
  const site::StereoImages images = site::RenderStereo(r.scene);
  for (size_t i = 0; i < r.scene.objects.size(); ++i) {
    if (r.scene.objects[i].name != name) continue;
    r.shape = r.scene.objects[i].shape;
    r.present = true;
    r.input.marks = *site::GenerateMarks(r.shape, r.scene.cameras.left, seed * 1000 + i);
    r.input.type =
        std::holds_alternative<site::Cylinder>(r.shape) ? SolidType::kCylinder : SolidType::kBox;
  }
  r.input.left = images.left;
  r.input.right = images.right;
  r.input.left_camera = r.scene.cameras.left;
  r.input.right_camera = r.scene.cameras.right;
  return r;
}

// The request's pipe located with `options`: found, its radius, length and centre within the
// tolerances given (world units).
struct PipeTolerance {
  double radius = 0.03, length = 0.1, centre = 0.1;
};
inline LocateResult ExpectPipeFound(const SiteRequest& r, const PipeTolerance& tolerance = {},
                                    const LocateOptions& options = {}) {
  EXPECT_TRUE(r.present);
  const auto* truth = std::get_if<site::Cylinder>(&r.shape);
  LocateResult found = Locate(r.input, options);
  EXPECT_TRUE(found.found) << found.detail;
  if (!found.found || !truth) return found;
  EXPECT_NEAR(found.cylinder.radius, truth->radius, tolerance.radius);
  EXPECT_NEAR(found.cylinder.height, truth->height, tolerance.length);
  EXPECT_LT((found.cylinder.center - truth->center).norm(), tolerance.centre);
  return found;
}

// The request located with `options` (a step turned off): refused, for `reason`.
inline void ExpectRefused(const SiteRequest& r, const LocateOptions& options, Failure reason) {
  const LocateResult refused = Locate(r.input, options);
  EXPECT_FALSE(refused.found);
  EXPECT_EQ(refused.reason, reason) << refused.detail;
}

}  // namespace igms::object
