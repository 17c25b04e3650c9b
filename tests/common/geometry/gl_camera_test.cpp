// The graphical camera: OpenGL's transform chain with our matrices puts every world point on
// the pixel P projects it to, within 0.01 px, for both thesis cameras and skewed synthetic ones.
#include "common/geometry/gl_camera.h"

#include <gtest/gtest.h>

#include "tests/common/geometry/synthetic_rig.h"

namespace igms::geometry {
namespace {

Matrix34 ThesisLeft() {
  Matrix34 C;
  C << -232.71, -64.35, 4.45, 5031.32, -5.22, -63.50, -285.65, 1379.56, -0.01, -0.24, 0.01, 1.00;
  return C;
}
Matrix34 ThesisRight() {
  Matrix34 C;
  C << -214.44, -60.906, 4.84, 3844.42, -4.93, -58.97, -261.44, 1294.73, -0.01, -0.22, 0.01, 1.00;
  return C;
}

void ExpectRegistered(const Matrix34& P, ImageSize size, double near, double far, int seed) {
  const ProjectiveCamera cam(P, size);
  const auto gl = MakeGlCamera(P, size, near, far);
  ASSERT_TRUE(gl.ok());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, size.width - 0.5), v(-0.5, size.height - 0.5),
      depth(near * 1.01, far * 0.99);
  double worst = 0;
  for (int i = 0; i < 2000; ++i) {
    // A world point seen at a random pixel and depth inside the view volume.
    const Ray ray = cam.PixelRay({u(rng), v(rng)});
    const double cosine = ray.direction.dot(cam.ViewDirection());
    const Eigen::Vector3d X = ray.At(depth(rng) / cosine);
    const auto expected = cam.Project(X);
    const auto drawn = GlPixel(*gl, size, X);
    ASSERT_TRUE(expected && drawn);
    worst = std::max(worst, (*drawn - *expected).norm());
    // Inside the clipping volume.
    const Eigen::Vector4d clip = gl->projection * gl->view * X.homogeneous();
    EXPECT_LE(std::abs(clip.z() / clip.w()), 1.0);
  }
  EXPECT_LT(worst, 0.01);
  // NDC depth is -1 at near and +1 at far along the axis.
  const Eigen::Vector3d c = cam.Center(), d = cam.ViewDirection();
  const Eigen::Vector4d at_near = gl->projection * gl->view * (c + near * d).homogeneous();
  const Eigen::Vector4d at_far = gl->projection * gl->view * (c + far * d).homogeneous();
  EXPECT_NEAR(at_near.z() / at_near.w(), -1.0, 1e-9);
  EXPECT_NEAR(at_far.z() / at_far.w(), 1.0, 1e-9);
  EXPECT_FALSE(GlPixel(*gl, size, c - 10 * d));
}

TEST(GlCamera, ThesisCamerasRegisterWithinHundredthPixel) {
  ExpectRegistered(ThesisLeft(), {512, 480}, 6, 200, 40);
  ExpectRegistered(ThesisRight(), {512, 480}, 6, 200, 41);
}

TEST(GlCamera, SkewedAndOffCentreCamerasRegister) {
  Eigen::Matrix3d K = testing::Intrinsics(1400, 700, 380, 0.9);
  K(0, 1) = 12;
  ExpectRegistered(testing::LookAt(K, {1, 2, 3}, {40, -20, 0}), {1280, 1024}, 1, 500, 42);
  ExpectRegistered(-0.01 * testing::ThesisLikeRig().right.P(), {512, 480}, 10, 120, 43);
}

TEST(GlCamera, ReportsFieldOfViewAndRefusesBadInput) {
  const auto gl =
      MakeGlCamera(testing::LookAt(testing::Intrinsics(1000, 255.5, 239.5), {0, 0, 0}, {1, 0, 0}),
                   {512, 480}, 1, 100);
  ASSERT_TRUE(gl.ok());
  EXPECT_NEAR(gl->fovy_degrees, 2 * std::atan(240.0 / 1000) * 180 / M_PI, 1e-9);
  EXPECT_NEAR(gl->aspect, 512.0 / 480.0, 1e-12);
  EXPECT_LT(gl->principal_offset.norm(), 1e-9);
  EXPECT_FALSE(MakeGlCamera(ThesisLeft(), {512, 480}, 0, 100).ok());
  EXPECT_FALSE(MakeGlCamera(ThesisLeft(), {512, 480}, 10, 5).ok());
  EXPECT_FALSE(MakeGlCamera(ThesisLeft(), {0, 480}, 1, 5).ok());
  EXPECT_FALSE(MakeGlCamera(Matrix34::Zero(), {512, 480}, 1, 5).ok());
}

}  // namespace
}  // namespace igms::geometry
