// Scene files, ground truth, range along a beam, and generated operator marks.
#include <gtest/gtest.h>

#include <cmath>

#include "common/sim/marks.h"
#include "common/sim/range.h"
#include "common/sim/scene_yaml.h"
#include "common/sim/testbed.h"

namespace igms::site {
namespace {

TEST(SceneYaml, RoundTripsTheDefaultScene) {
  const Scene a = DefaultTestbedScene();
  const SceneLoad load = ParseSceneYaml(SceneToYaml(a));
  ASSERT_TRUE(load.scene) << load.error;
  const Scene& b = *load.scene;
  ASSERT_EQ(a.objects.size(), b.objects.size());
  EXPECT_TRUE(a.cameras.left.P().isApprox(b.cameras.left.P()));
  EXPECT_TRUE(a.cameras.right.P().isApprox(b.cameras.right.P()));
  for (size_t i = 0; i < a.objects.size(); ++i) {
    EXPECT_EQ(a.objects[i].name, b.objects[i].name);
    EXPECT_EQ(KindName(a.objects[i].shape), KindName(b.objects[i].shape));
    if (auto* c = std::get_if<Cylinder>(&a.objects[i].shape)) {
      const auto& d = std::get<Cylinder>(b.objects[i].shape);
      EXPECT_TRUE(c->center.isApprox(d.center));
      EXPECT_DOUBLE_EQ(c->radius, d.radius);
      EXPECT_DOUBLE_EQ(c->height, d.height);
    }
  }
}

TEST(SceneYaml, ParsesObjectsAndRejectsBadInput) {
  const SceneLoad ok = ParseSceneYaml(R"(
sensor: {noise_sigma: 0, blur_sigma: 0, seed: 7}
objects:
  - {name: pipe, type: cylinder, center: [20, -60, 0.5], axis: [1, 0, 0], radius: 0.5, height: 6}
  - {type: box, center: [10, -50, 1], size: [2, 2, 2], rpy_deg: [0, 0, 30]}
  - {type: sphere, center: [25, -40, 1], radius: 1, texture: {contrast: 0.4, period: 0.75}}
)");
  ASSERT_TRUE(ok.scene) << ok.error;
  EXPECT_EQ(ok.scene->objects.size(), 3u);
  EXPECT_FALSE(ok.scene->objects[1].texture.enabled());
  EXPECT_DOUBLE_EQ(ok.scene->objects[2].texture.contrast, 0.4);
  EXPECT_DOUBLE_EQ(ok.scene->objects[2].texture.period, 0.75);
  const SceneLoad again = ParseSceneYaml(SceneToYaml(*ok.scene));
  ASSERT_TRUE(again.scene) << again.error;
  EXPECT_DOUBLE_EQ(again.scene->objects[2].texture.period, 0.75);
  EXPECT_EQ(ok.scene->sensor.seed, 7u);
  EXPECT_EQ(ok.scene->objects[0].name, "pipe");
  const auto& box = std::get<Box>(ok.scene->objects[1].shape);
  EXPECT_NEAR(box.rotation(1, 0), 0.5, 1e-12);
  for (const char* bad : {"objects: [{type: cone}]", "objects: [{type: cylinder, radius: -1}]",
                          "objects: [{type: box, size: [1, 2]}]", "cameras: {left: [1, 2, 3]}",
                          "objects: {a: 1}", "[unclosed", "sensor: {noise_sigma: -1}",
                          "objects: [{type: sphere, texture: {contrast: 2}}]",
                          "objects: [{type: sphere, texture: {period: 0}}]",
                          "objects: [{type: sphere, texture: 3}]"}) {
    const SceneLoad load = ParseSceneYaml(bad);
    EXPECT_FALSE(load.scene) << bad;
    EXPECT_FALSE(load.error.empty()) << bad;
  }
  EXPECT_FALSE(LoadSceneFile("/nonexistent/scene.yaml").scene);
}

TEST(Range, MatchesAnalyticDistances) {
  Scene s = DefaultTestbedScene();
  s.objects.clear();
  Cylinder c;
  c.center = {20, -50, 3};
  c.radius = 0.5;
  c.height = 6;
  s.objects.push_back({"c", c, 0.85});
  const Eigen::Vector3d origin(
      20, 0, 5.5);  // high enough that a 5 degree cone misses the table before 49.5 in
  // Straight at the cylinder: the front surface at 50 - 0.5.
  EXPECT_NEAR(*CastRay(s, origin, {0, -1, 0}), 49.5, 1e-9);
  // A cone: its nearest surface is still the front of the cylinder.
  EXPECT_NEAR(*RangeInCone(s, origin, {0, -1, 0}, 5 * M_PI / 180), 49.5, 1e-9);
  // Off the axis by 0.3 in: the circle's chord, sqrt(r^2 - 0.3^2) short of the centre.
  EXPECT_NEAR(*CastRay(s, {20.3, 0, 5.5}, {0, -1, 0}), 50 - std::sqrt(0.25 - 0.09), 1e-9);
  // Down at the table from 10 in up, 45 degrees: 10 * sqrt(2).
  EXPECT_NEAR(*CastRay(s, {10, -40, 10}, {0, -1, -1}), 10 * std::sqrt(2.0), 1e-9);
  // A cone aimed past the cylinder's side still catches it: nearer than the table behind.
  const auto wide = RangeInCone(s, origin, Eigen::Vector3d(0.03, -1, 0), 4 * M_PI / 180);
  ASSERT_TRUE(wide);
  EXPECT_LT(*wide, 50.0);
  EXPECT_GT(*wide, 49.4);
  // Up into the sky: nothing.
  EXPECT_FALSE(CastRay(s, origin, {0, 0, 1}));
}

TEST(Marks, BoundTheSilhouetteAtAnErroneousDepth) {
  const Scene s = RandomTestbedScene(5);
  for (size_t i = 0; i < s.objects.size(); ++i) {
    const auto marks = GenerateMarks(s.objects[i].shape, s.cameras.left, 100 + i);
    ASSERT_TRUE(marks);
    double u0, v0, u1, v1;
    ASSERT_TRUE(ImageBounds(s.objects[i].shape, s.cameras.left, u0, v0, u1, v1));
    const double front = FrontDepth(s.objects[i].shape, s.cameras.left);
    double umin = 1e9, umax = -1e9, vmin = 1e9, vmax = -1e9;
    for (const auto& m : *marks) {
      EXPECT_LE(std::abs(s.cameras.left.Depth(m) - front), 3.0 + 1e-9);
      const auto p = *s.cameras.left.Project(m);
      umin = std::min(umin, p.x());
      umax = std::max(umax, p.x());
      vmin = std::min(vmin, p.y());
      vmax = std::max(vmax, p.y());
    }
    // Outside the silhouette's box on every side (0.2 in margin less 3 sigma of jitter).
    EXPECT_LT(umin, u0);
    EXPECT_GT(umax, u1);
    EXPECT_LT(vmin, v0);
    EXPECT_GT(vmax, v1);
  }
}

TEST(Testbed, RandomScenesFitInBothImages) {
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const Scene s = RandomTestbedScene(seed);
    EXPECT_GE(s.objects.size(), 3u);
    for (const auto& o : s.objects) {
      for (const auto* cam : {&s.cameras.left, &s.cameras.right}) {
        double u0, v0, u1, v1;
        ASSERT_TRUE(ImageBounds(o.shape, *cam, u0, v0, u1, v1));
        EXPECT_GE(u0, 0);
        EXPECT_GE(v0, 0);
        EXPECT_LE(u1, 511);
        EXPECT_LE(v1, 479);
      }
    }
  }
}

}  // namespace
}  // namespace igms::site
