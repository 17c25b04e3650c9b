// The locator's steps on a rendered testbed scene (the tests of object_server/locate_steps.h):
// a scene with its first upright cylinder and its first box marked as the operator's marks
// are modelled, and steps 0-3 run on it as Locate runs them.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "common/sim/marks.h"
#include "common/sim/renderer.h"
#include "common/sim/site_scenes.h"
#include "common/sim/testbed.h"
#include "object_server/locate_steps.h"
#include "object_server/solid_models.h"

namespace igms::object::testing {

inline bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A cylinder of a site scene (common/sim/site_scenes.h) asked for as EvaluateScene asks: the
// scene rendered, and the operator's marks from mark_seed * 1000 + the cylinder's index.
struct SiteCylinder {
  site::Scene scene;
  site::Cylinder pipe;
  LocateInput input;
};
inline SiteCylinder MarkedSiteCylinder(uint64_t seed, site::SiteLevel level, bool hd,
                                       const std::string& name, uint64_t mark_seed) {
  SiteCylinder c;
  c.scene = site::SiteScene(seed, level, hd);
  const site::StereoImages images = site::RenderStereo(c.scene);
  size_t index = 0;
  while (index < c.scene.objects.size() && c.scene.objects[index].name != name) ++index;
  EXPECT_LT(index, c.scene.objects.size()) << name;
  if (index == c.scene.objects.size()) return c;
  c.pipe = std::get<site::Cylinder>(c.scene.objects[index].shape);
  c.input.type = SolidType::kCylinder;
  c.input.marks = *site::GenerateMarks(c.pipe, c.scene.cameras.left, mark_seed * 1000 + index);
  c.input.left = images.left;
  c.input.right = images.right;
  c.input.left_camera = c.scene.cameras.left;
  c.input.right_camera = c.scene.cameras.right;
  return c;
}

// The convex outline of a cylinder's parameters in each view.
inline std::array<std::vector<Eigen::Vector2d>, 2> CylinderOutlines(
    const Eigen::VectorXd& params, const std::array<FitView, 2>& views) {
  std::array<std::vector<Eigen::Vector2d>, 2> out;
  for (int v = 0; v < 2; ++v) {
    std::vector<Eigen::Vector2d> px;
    for (const auto& X : CylinderOutline(params)) px.push_back(*views[v].camera->Project(X));
    out[v] = ConvexHull(px);
  }
  return out;
}

// A rendered scene with its first upright cylinder and its first box marked.
class LocateSteps : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new site::Scene(site::RandomTestbedScene(42));
    images_ = new site::StereoImages(site::RenderStereo(*scene_));
  }
  static void TearDownTestSuite() {
    delete images_;
    delete scene_;
  }
  void SetUp() override {
    for (size_t i = 0; i < scene_->objects.size(); ++i) {
      const auto& shape = scene_->objects[i].shape;
      if (const auto* c = std::get_if<site::Cylinder>(&shape); c && !cylinder_ && c->axis.z() > 0.9)
        cylinder_ = c;
      if (const auto* b = std::get_if<site::Box>(&shape); b && !box_) box_ = b;
    }
    ASSERT_NE(cylinder_, nullptr);
    ASSERT_NE(box_, nullptr);
  }
  LocateInput Input(bool cylinder) const {
    LocateInput in;
    in.type = cylinder ? SolidType::kCylinder : SolidType::kBox;
    const site::Shape shape = cylinder ? site::Shape(*cylinder_) : site::Shape(*box_);
    in.marks = *site::GenerateMarks(shape, scene_->cameras.left, 7);
    in.left = images_->left;
    in.right = images_->right;
    in.left_camera = scene_->cameras.left;
    in.right_camera = scene_->cameras.right;
    return in;
  }
  // The object's bounding rectangle in the left image.
  cv::Rect2d TrueBounds(const site::Shape& shape) const {
    double u0, v0, u1, v1;
    EXPECT_TRUE(site::ImageBounds(shape, scene_->cameras.left, u0, v0, u1, v1));
    return cv::Rect2d(u0, v0, u1 - u0, v1 - v0);
  }
  // Steps 0-3 of a good input, as Locate runs them.
  struct Through3 {
    StereoPair pair;
    MarkedRegion marks;
    Boundary boundary;
    DepthSearch search;
    SsdMatch match;
    double depth = 0;
  };
  Through3 RunThroughStep3(const LocateInput& in, const Gradients** grad_left = nullptr) {
    Through3 t;
    const auto pair = PrepareImages(in);
    EXPECT_TRUE(pair.ok()) << pair.failure().detail;
    t.pair = *pair;
    const auto marks = MarkRegion(in);
    EXPECT_TRUE(marks.ok()) << marks.failure().detail;
    t.marks = *marks;
    const cv::Rect image(0, 0, t.pair.left.cols, t.pair.left.rows);
    left_gradients_ =
        Gradients(t.pair.left, GrowRect(cv::boundingRect(t.marks.hull), RegionPad(options_), image),
                  options_.edge_sigma);
    if (grad_left) *grad_left = &left_gradients_;
    t.boundary = FindBoundary(left_gradients_, t.marks, cv::Mat(), options_);
    t.search = ObjectDepthSearch(t.boundary.pixels, t.marks.depth, options_);
    const auto match = MatchObject(t.pair, t.search, options_);
    EXPECT_TRUE(match.ok()) << match.failure().detail;
    t.match = *match;
    const auto x = TriangulateMatch(t.pair, t.search, t.match);
    EXPECT_TRUE(x.has_value());
    t.depth = x ? in.left_camera.Depth(*x) : 0;
    return t;
  }

  // Both views for the fit after RunThroughStep3: the right image's gradients over the patch
  // moved by the match.
  std::array<FitView, 2> FitViews(const LocateInput& in, const Through3& t) {
    const cv::Rect image(0, 0, t.pair.right.cols, t.pair.right.rows);
    right_gradients_ =
        Gradients(t.pair.right, RightRegion(t.search, t.match, RegionPad(options_), image),
                  options_.edge_sigma);
    return {FitView{&in.left_camera, &left_gradients_},
            FitView{&in.right_camera, &right_gradients_}};
  }

  inline static site::Scene* scene_ = nullptr;
  inline static site::StereoImages* images_ = nullptr;
  const site::Cylinder* cylinder_ = nullptr;
  const site::Box* box_ = nullptr;
  LocateOptions options_;
  Gradients left_gradients_, right_gradients_;
};

}  // namespace igms::object::testing
