// The renderer against the camera model: a cylinder's anti-aliased silhouette lies where the
// projection of its limb lines says, to 0.05 px, on the noiseless image.
#include "common/sim/renderer.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/sim/testbed.h"

namespace igms::site {
namespace {

// A flat-lit scene (ambient only), so the object and the background are each one grey level
// and a pixel's value measures how much of it the object covers.
Scene FlatScene(const Cylinder& c) {
  Scene s;
  s.cameras = ThesisCameras();
  s.lighting.ambient = 1.0;
  s.lighting.lights.clear();
  s.table.enabled = false;
  s.table.background = 0.03;
  s.objects = {{"c", c, 0.8}};
  return s;
}

// Pixel u where the camera model puts the limb line through tangent point T (a vertical
// line) on image row v.
double LimbU(const geometry::ProjectiveCamera& cam, const Eigen::Vector2d& t, double v) {
  double lo = -50, hi = 50;  // z range; v decreases as z grows
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (cam.Project({t.x(), t.y(), mid})->y() > v)
      lo = mid;
    else
      hi = mid;
  }
  return cam.Project({t.x(), t.y(), 0.5 * (lo + hi)})->x();
}

TEST(Renderer, CylinderSilhouetteMatchesCameraModel) {
  Cylinder c;
  c.center = {19.0, -50.0, 3.0};
  c.axis = Eigen::Vector3d::UnitZ();
  c.radius = 0.5;
  c.height = 6.0;
  for (bool right_camera : {false, true}) {
    const Scene scene = FlatScene(c);
    const auto& cam = right_camera ? scene.cameras.right : scene.cameras.left;
    RenderOptions options;
    options.apply_sensor = false;
    const cv::Mat img = Render(scene, cam, 0, options);
    const double bg = 255 * 0.03, fg = 255 * 0.8;
    // Tangent points of the limb lines, seen from the camera centre (top view).
    const Eigen::Vector3d C = cam.Center();
    const Eigen::Vector2d to_cam(C.x() - c.center.x(), C.y() - c.center.y());
    const double th0 = std::atan2(to_cam.y(), to_cam.x()),
                 phi = std::acos(c.radius / to_cam.norm());
    const Eigen::Vector2d t1 =
        c.center.head<2>() + c.radius * Eigen::Vector2d(std::cos(th0 + phi), std::sin(th0 + phi));
    const Eigen::Vector2d t2 =
        c.center.head<2>() + c.radius * Eigen::Vector2d(std::cos(th0 - phi), std::sin(th0 - phi));
    const double top_v = cam.Project(c.Top())->y(), bottom_v = cam.Project(c.Base())->y();
    double worst = 0;
    int rows = 0;
    for (int v = static_cast<int>(top_v) + 5; v < static_cast<int>(bottom_v) - 5; v += 3) {
      const double ua = LimbU(cam, t1, v), ub = LimbU(cam, t2, v);
      const double left_u = std::min(ua, ub), right_u = std::max(ua, ub);
      // Left edge: from the last full background pixel to the first full object pixel.
      const uint8_t* row = img.ptr<uint8_t>(v);
      int x = static_cast<int>(left_u) - 4;
      while (row[x] < fg - 0.5) ++x;  // first fully covered pixel
      double covered = 0;
      for (int k = x - 1; row[k] > bg + 0.5; --k) covered += (row[k] - bg) / (fg - bg);
      const double measured_left = x - 0.5 - covered;
      int y = static_cast<int>(right_u) + 4;
      while (row[y] < fg - 0.5) --y;  // last fully covered pixel
      covered = 0;
      for (int k = y + 1; row[k] > bg + 0.5; ++k) covered += (row[k] - bg) / (fg - bg);
      const double measured_right = y + 0.5 + covered;
      worst =
          std::max({worst, std::abs(measured_left - left_u), std::abs(measured_right - right_u)});
      ++rows;
    }
    EXPECT_GT(rows, 20);
    EXPECT_LT(worst, 0.05) << (right_camera ? "right" : "left") << " camera";
  }
}

// A textured box shows its pattern inside the silhouette (grey levels vary with the
// texture's contrast), with the plain box's mean, and the same silhouette.
TEST(Renderer, TexturedMaterialVariesInsideTheSilhouette) {
  Box b;
  b.center = {19.0, -50.0, 2.0};
  b.size = {4.0, 4.0, 4.0};
  Scene scene = FlatScene(Cylinder{});
  scene.objects = {{"plain", b, 0.6}};
  RenderOptions options;
  options.apply_sensor = false;
  const cv::Mat plain = Render(scene, scene.cameras.left, 0, options);
  scene.objects[0].texture.contrast = 0.5;
  scene.objects[0].texture.period = 1.0;
  const cv::Mat textured = Render(scene, scene.cameras.left, 0, options);
  // The box's inner image: well inside the projection of its front face's centre.
  const Eigen::Vector2d c = *scene.cameras.left.Project(b.center);
  const cv::Rect inner(static_cast<int>(c.x()) - 10, static_cast<int>(c.y()) - 10, 20, 20);
  cv::Scalar plain_mean, plain_sd, tex_mean, tex_sd;
  cv::meanStdDev(plain(inner), plain_mean, plain_sd);
  cv::meanStdDev(textured(inner), tex_mean, tex_sd);
  EXPECT_LT(plain_sd[0], 0.6);  // one grey level, flat lit
  EXPECT_GT(tex_sd[0], 10.0);   // 0.5 contrast of 153 grey levels
  EXPECT_NEAR(tex_mean[0], plain_mean[0], 20.0);
  // Outside the box nothing changed.
  cv::Mat differ = plain != textured, outside = cv::Mat::ones(plain.size(), CV_8U);
  const std::vector<Eigen::Vector3d> corners = OutlinePoints(b);
  double u0 = 1e9, u1 = -1e9, v0 = 1e9, v1 = -1e9;
  for (const auto& p : corners) {
    const Eigen::Vector2d q = *scene.cameras.left.Project(p);
    u0 = std::min(u0, q.x()), u1 = std::max(u1, q.x()), v0 = std::min(v0, q.y()),
    v1 = std::max(v1, q.y());
  }
  outside(cv::Rect(cv::Point(static_cast<int>(u0) - 1, static_cast<int>(v0) - 1),
                   cv::Point(static_cast<int>(u1) + 3, static_cast<int>(v1) + 3))) = 0;
  EXPECT_EQ(cv::countNonZero(differ & outside), 0);
}

TEST(Renderer, SensorModelIsSeededAndBounded) {
  Scene scene = DefaultTestbedScene();
  const auto a = RenderStereo(scene), b = RenderStereo(scene);
  EXPECT_EQ(cv::norm(a.left, b.left, cv::NORM_INF), 0);
  scene.sensor.seed = 99;
  const auto c = RenderStereo(scene);
  EXPECT_GT(cv::norm(a.left, c.left, cv::NORM_L1), 0);
  // Noise of sigma 2: the difference of two independent draws has sigma 2*sqrt(2).
  cv::Mat diff;
  cv::subtract(a.left, c.left, diff, cv::noArray(), CV_32F);
  cv::Scalar mean, stddev;
  cv::meanStdDev(diff, mean, stddev);
  EXPECT_NEAR(stddev[0], 2 * std::sqrt(2.0), 0.3);
  EXPECT_EQ(a.left.type(), CV_8UC1);
  EXPECT_EQ(a.left.cols, 512);
  EXPECT_EQ(a.left.rows, 480);
}

}  // namespace
}  // namespace igms::site
