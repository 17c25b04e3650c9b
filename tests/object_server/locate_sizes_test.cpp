// A model whose size the images leave open is refused with its reason (object_server/locate.h:
// max_box_size_sigma), not reported inches off: on rendered site scenes.
#include <gtest/gtest.h>

#include <string>
#include <variant>

#include "common/sim/marks.h"
#include "common/sim/renderer.h"
#include "common/sim/site_scenes.h"
#include "object_server/locate.h"

namespace igms::object {
namespace {

// A site scene's object asked for as its own type with the benchmark's marks
// (common/sim/vision/evaluation.h).
LocateInput AskFor(uint64_t seed, site::SiteLevel level, bool hd, const std::string& name,
                   site::Shape* shape) {
  const site::Scene scene = site::SiteScene(seed, level, hd);
  const site::StereoImages images = site::RenderStereo(scene);
  LocateInput in;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    if (scene.objects[i].name != name) continue;
    *shape = scene.objects[i].shape;
    in.marks = *site::GenerateMarks(*shape, scene.cameras.left, seed * 1000 + i);
    in.type =
        std::holds_alternative<site::Cylinder>(*shape) ? SolidType::kCylinder : SolidType::kBox;
  }
  in.left = images.left;
  in.right = images.right;
  in.left_camera = scene.cameras.left;
  in.right_camera = scene.cameras.right;
  return in;
}

TEST(SizesDetermined, APipeWhoseLengthNothingHoldsIsRefused) {
  // Level clutter, seed 7008: upright_6, in full view among others; neither its top nor its
  // limbs' end holds its height.
  site::Shape shape;
  const LocateInput in = AskFor(7008, site::SiteLevel::kClutter, false, "upright_6", &shape);
  ASSERT_TRUE(std::holds_alternative<site::Cylinder>(shape));
  const LocateResult refused = Locate(in);
  EXPECT_FALSE(refused.found);
  EXPECT_EQ(refused.reason, Failure::kFitFailed);
  EXPECT_NE(refused.detail.find("do not determine the cylinder's length"), std::string::npos)
      << refused.detail;
  // Without the bound it is reported, its length's sigma saying it is unknown.
  LocateOptions unbounded;
  unbounded.max_box_size_sigma = 1e9;
  const LocateResult reported = Locate(in, unbounded);
  ASSERT_TRUE(reported.found) << reported.detail;
  EXPECT_GT(reported.cylinder.height_sigma, 50);
}

}  // namespace
}  // namespace igms::object
