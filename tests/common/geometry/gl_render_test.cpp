// The graphical camera through a real OpenGL pipeline (Mesa, under Xvfb): world points whose
// P-pixels lie 0.01 px either side of a pixel boundary must light the pixel on their side.
// That bounds the registration error of the GL matrices, as OpenGL itself draws them, by
// 0.01 px, for both thesis cameras (equations 4.1 and 4.2) over thousands of points.
#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "common/geometry/gl_camera.h"

namespace igms::geometry {
namespace {

constexpr ImageSize kSize{512, 480};

Matrix34 Thesis(int side) {
  Matrix34 C;
  if (side == 0) {
    C << -232.71, -64.35, 4.45, 5031.32, -5.22, -63.50, -285.65, 1379.56, -0.01, -0.24, 0.01, 1.00;
  } else {
    C << -214.44, -60.906, 4.84, 3844.42, -4.93, -58.97, -261.44, 1294.73, -0.01, -0.22, 0.01, 1.00;
  }
  return C;
}

class GlRender : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(glfwInit()) << "no display: run under xvfb-run";
    glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
    window_ = glfwCreateWindow(kSize.width, kSize.height, "gl_render_test", nullptr, nullptr);
    ASSERT_NE(window_, nullptr);
    glfwMakeContextCurrent(window_);
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    ASSERT_EQ(w, kSize.width);
    ASSERT_EQ(h, kSize.height);
  }
  void TearDown() override {
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
  }
  GLFWwindow* window_ = nullptr;
};

TEST_F(GlRender, PointsLandOnTheirPixelWithinAHundredth) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> depth(24, 120);
  std::bernoulli_distribution coin(0.5);
  int checked = 0, wrong = 0;
  for (int side = 0; side < 2; ++side) {
    const ProjectiveCamera cam(Thesis(side), kSize);
    const auto gl = MakeGlCamera(cam.P(), kSize, 6, 300);
    ASSERT_TRUE(gl.ok());
    for (int offset_u = 0; offset_u < 4; ++offset_u) {
      // Targets 4 px apart; each 0.49 or 0.51 px from its pixel centre along u and v, so the
      // correct pixel is decided by 0.01 px.
      struct Target {
        int u, v;
        Eigen::Vector3d world;
      };
      std::vector<Target> targets;
      for (int v = 2 + offset_u; v < kSize.height - 2; v += 4) {
        for (int u = 2 + offset_u; u < kSize.width - 2; u += 4) {
          const double du = (coin(rng) ? 0.49 : 0.51) * (coin(rng) ? 1 : -1);
          const double dv = (coin(rng) ? 0.49 : 0.51) * (coin(rng) ? 1 : -1);
          const Eigen::Vector2d pixel(u + du, v + dv);
          const Ray ray = cam.PixelRay(pixel);
          const Eigen::Vector3d X = ray.At(depth(rng) / ray.direction.dot(cam.ViewDirection()));
          targets.push_back({static_cast<int>(std::lround(pixel.x())),
                             static_cast<int>(std::lround(pixel.y())), X});
        }
      }
      glViewport(0, 0, kSize.width, kSize.height);
      glClearColor(0, 0, 0, 1);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      glDisable(GL_DEPTH_TEST);
      glDisable(GL_POINT_SMOOTH);
      glDisable(GL_MULTISAMPLE);
      glPointSize(1.0f);
      glMatrixMode(GL_PROJECTION);
      glLoadMatrixd(gl->projection.data());
      glMatrixMode(GL_MODELVIEW);
      glLoadMatrixd(gl->view.data());
      glColor3f(1, 1, 1);
      glBegin(GL_POINTS);
      for (const auto& t : targets) glVertex3d(t.world.x(), t.world.y(), t.world.z());
      glEnd();
      glFinish();
      std::vector<unsigned char> image(static_cast<std::size_t>(kSize.width) * kSize.height);
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      glReadBuffer(GL_BACK);
      glReadPixels(0, 0, kSize.width, kSize.height, GL_RED, GL_UNSIGNED_BYTE, image.data());
      auto lit = [&](int u, int v) {  // IGMS pixel (u, v): GL row height - 1 - v
        return image[(kSize.height - 1 - v) * kSize.width + u] > 127;
      };
      int lit_total = 0;
      for (unsigned char c : image) lit_total += c > 127;
      EXPECT_EQ(lit_total, static_cast<int>(targets.size())) << "one pixel per point";
      for (const auto& t : targets) {
        ++checked;
        if (!lit(t.u, t.v)) ++wrong;
      }
    }
  }
  EXPECT_GT(checked, 20000);
  EXPECT_EQ(wrong, 0) << wrong << " of " << checked << " points on the wrong pixel";
}

}  // namespace
}  // namespace igms::geometry
