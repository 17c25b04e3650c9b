// A block's silhouette edges beside a thin face (object_server/locate_steps.h: BoxFaceShifts,
// RefineBoxForFaces): on rendered testbed scenes, whose blocks came out about a hundredth of an
// inch too tall before, their top face, a few pixels tall and brighter than the front, pushing
// the outline's top edge out.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <variant>
#include <vector>

#include "common/sim/renderer.h"
#include "common/sim/testbed.h"
#include "object_server/locate_steps.h"
#include "tests/object_server/testbed_twice.h"

namespace igms::object {
namespace {

// The shifts BoxFaceShifts gives in the left image for the scene's block at its true pose.
std::vector<double> TrueBlockShifts(const site::Scene& scene) {
  const site::Box* box = nullptr;
  for (const auto& o : scene.objects)
    if (const auto* b = std::get_if<site::Box>(&o.shape)) box = b;
  EXPECT_NE(box, nullptr);
  if (!box) return {};
  const site::StereoImages images = site::RenderStereo(scene);
  LocateInput in;
  in.left = images.left;
  in.right = images.right;
  in.left_camera = scene.cameras.left;
  in.right_camera = scene.cameras.right;
  const auto pair = PrepareImages(in);
  EXPECT_TRUE(pair.ok());
  if (!pair.ok()) return {};
  const LocateOptions options;
  const Gradients gradients(pair->left, cv::Rect(0, 0, pair->left.cols, pair->left.rows),
                            options.edge_sigma);
  Eigen::VectorXd x(7);
  x << box->center, box->size, std::atan2(box->rotation(1, 0), box->rotation(0, 0));
  return BoxFaceShifts(pair->left, scene.cameras.left, gradients, x, {},
                       FitSettings(options, 0).min_gradient, options.max_face_px);
}

TEST(BoxFaceShifts, MoveEdgesBesideAThinFaceOnlyWhereTheFacesShadeApart) {
  // Seed 1000: at the block's true pose, the edge search finds the silhouette's side 0.64 px
  // inside it, drawn in by the step from the bright front face to a dim side face 2.2 px wide;
  // the profile's model puts the edge where it is.
  site::Scene scene = site::RandomTestbedScene(1000);
  const std::vector<double> lit = TrueBlockShifts(scene);
  ASSERT_EQ(lit.size(), 8u);
  int moved = 0;
  for (const double s : lit) {
    EXPECT_LT(std::abs(s), 1.0);
    moved += std::abs(s) > 0.05;
  }
  EXPECT_GE(moved, 1);
  EXPECT_GT(*std::max_element(lit.begin(), lit.end()), 0.3);  // out, to the true side
  // Lit by ambient light alone every face has the same shade: the edges stay.
  scene.lighting.ambient = 0.8;
  scene.lighting.lights.clear();
  for (const double s : TrueBlockShifts(scene)) EXPECT_LT(std::abs(s), 0.06);
}

TEST(RefineBoxForFaces, BlocksComeOutCloserToTheirTrueSize) {
  LocateOptions moved = SiteLocateOptions(), kept = moved;
  kept.max_face_shading_px = 0;
  int blocks = 0, changed = 0;
  double height_before = 0, height_after = 0, tall_before = 0, sizes_before = 0, sizes_after = 0;
  for (const auto& [name, before, after] : EvaluateTestbedTwice(1000, 1010, kept, moved)) {
    if (after.kind != "box" || !before.result.found || !after.result.found) continue;
    ++blocks;
    changed += before.result.box.size != after.result.box.size;
    height_before += std::abs(before.size_signed.z());
    height_after += std::abs(after.size_signed.z());
    tall_before += before.size_signed.z();
    sizes_before += before.size_signed.cwiseAbs().sum();
    sizes_after += after.size_signed.cwiseAbs().sum();
    // The sigmas are the first fit's covariance's.
    EXPECT_LT((before.result.box.size_sigma - after.result.box.size_sigma).norm(),
              0.01 * before.result.box.size_sigma.norm())
        << name;
  }
  ASSERT_GE(blocks, 8);
  EXPECT_GE(changed, 4);
  // Before: too tall on the whole; after, closer in height and in all three sizes.
  EXPECT_GT(tall_before / blocks, 0.004);
  EXPECT_LT(height_after, 0.8 * height_before);
  EXPECT_LT(sizes_after, sizes_before);
}

TEST(RefineBoxForFaces, ItsBoundsAreChecked) {
  std::string error;
  for (const double bad : {-0.1, std::nan("")}) {
    LocateOptions options;
    options.max_face_shading_px = bad;
    EXPECT_FALSE(options.Check(&error)) << bad;
    EXPECT_NE(error.find("max_face_shading_px"), std::string::npos) << error;
    LocateOptions wide;
    wide.max_face_px = bad;
    EXPECT_FALSE(wide.Check(&error)) << bad;
    EXPECT_NE(error.find("max_face_px"), std::string::npos) << error;
  }
}

}  // namespace
}  // namespace igms::object
