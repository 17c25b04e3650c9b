// Camera model: projection, rays, inverse perspective (thesis 3.5) and lens distortion,
// against synthetic ground truth and against OpenCV's own distortion model.
#include "common/geometry/camera.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "common/geometry/distortion.h"
#include "common/geometry/inverse_perspective.h"
#include "tests/common/geometry/synthetic_rig.h"

namespace igms::geometry {
namespace {

using testing::RandomScenePoint;
using testing::ThesisLikeRig;

double DistanceToRay(const Ray& ray, const Eigen::Vector3d& p) {
  const Eigen::Vector3d v = p - ray.origin;
  return (v - v.dot(ray.direction) * ray.direction).norm();
}

TEST(Camera, ProjectThenRayPassesThroughThePoint) {
  const auto rig = ThesisLikeRig();
  std::mt19937 rng(1);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d X = RandomScenePoint(rng);
    for (const auto* cam : {&rig.left, &rig.right}) {
      const auto px = cam->Project(X);
      ASSERT_TRUE(px);
      const Ray ray = cam->PixelRay(*px);
      EXPECT_LT(DistanceToRay(ray, X), 1e-9);
      EXPECT_GT(ray.direction.dot(X - ray.origin), 0) << "ray must point into the scene";
      EXPECT_NEAR(ray.direction.norm(), 1.0, 1e-12);
    }
  }
}

TEST(Camera, CenterDepthAndViewDirectionIgnoreScaleAndSign) {
  const auto rig = ThesisLikeRig();
  const Eigen::Vector3d X(60, 1, 3);
  const double depth = rig.left.Depth(X);
  const Eigen::Vector3d expected_dir =
      (Eigen::Vector3d(60, 0, 2) - Eigen::Vector3d(0, 2, 6)).normalized();
  EXPECT_NEAR((rig.left.Center() - Eigen::Vector3d(0, 2, 6)).norm(), 0, 1e-9);
  EXPECT_NEAR((rig.left.ViewDirection() - expected_dir).norm(), 0, 1e-12);
  EXPECT_NEAR(depth, (X - rig.left.Center()).dot(expected_dir), 1e-9);
  for (double s : {-3.0, 1e-3, 250.0}) {
    const ProjectiveCamera scaled(s * rig.left.P(), {512, 480});
    EXPECT_NEAR(scaled.Depth(X), depth, 1e-9);
    EXPECT_NEAR((scaled.ViewDirection() - expected_dir).norm(), 0, 1e-12);
    EXPECT_NEAR((*scaled.Project(X) - *rig.left.Project(X)).norm(), 0, 1e-9);
    EXPECT_GT(scaled.PixelRay({10, 20}).direction.dot(expected_dir), 0);
  }
  EXPECT_LT(rig.left.Depth(Eigen::Vector3d(-10, 2, 6)), 0);
}

TEST(Camera, PointOnFocalPlaneDoesNotProject) {
  const auto rig = ThesisLikeRig();
  const Eigen::Vector3d dir = rig.left.ViewDirection();
  const Eigen::Vector3d side = dir.cross(Eigen::Vector3d::UnitZ()).normalized();
  EXPECT_FALSE(rig.left.Project(rig.left.Center() + 5 * side));
}

TEST(Camera, InImageUsesPixelCentreConvention) {
  const ProjectiveCamera cam = ThesisLikeRig().left;
  EXPECT_TRUE(cam.InImage({-0.5, -0.5}));
  EXPECT_TRUE(cam.InImage({511.5, 479.5}));
  EXPECT_FALSE(cam.InImage({511.6, 10}));
  EXPECT_FALSE(cam.InImage({10, -0.6}));
  EXPECT_FALSE(cam.InImage({0, 0}, 1.0));
}

TEST(InversePerspective, PlanesContainTheRayAndHeightPointIsOnIt) {
  const auto rig = ThesisLikeRig();
  std::mt19937 rng(2);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d X = RandomScenePoint(rng);
    const Eigen::Vector2d px = *rig.right.Project(X);
    const auto [p1, p2] = PixelPlanes(rig.right.P(), px);
    EXPECT_NEAR(p1.dot(X.homogeneous()) / p1.head<3>().norm(), 0, 1e-9);
    EXPECT_NEAR(p2.dot(X.homogeneous()) / p2.head<3>().norm(), 0, 1e-9);
    EXPECT_NEAR(p1.dot(rig.right.Center().homogeneous()) / p1.head<3>().norm(), 0, 1e-9);

    const auto line = LineFromPlanes(rig.right.P(), px);
    ASSERT_TRUE(line);
    EXPECT_LT(DistanceToRay(*line, X), 1e-9);
    EXPECT_NEAR(line->direction.dot(rig.right.PixelRay(px).direction), 1.0, 1e-12);

    const auto at_height = PointAtHeight(rig.right.P(), px, X.z());
    ASSERT_TRUE(at_height);
    EXPECT_LT((*at_height - X).norm(), 1e-8);

    const auto at_depth = PointAtDepth(rig.right, px, rig.right.Depth(X));
    ASSERT_TRUE(at_depth);
    EXPECT_LT((*at_depth - X).norm(), 1e-8);
  }
}

TEST(InversePerspective, HorizontalRayHasNoPointAtAHeight) {
  // A camera looking exactly along +x from height 6: the ray of the pixel at the horizon
  // stays at z = 6, so no point of it has z = 0.
  const Eigen::Matrix3d K = testing::Intrinsics(800, 256, 240);
  const Matrix34 P = testing::LookAt(K, {0, 0, 6}, {10, 0, 6});
  const ProjectiveCamera cam(P, {512, 480});
  const Eigen::Vector2d horizon = *cam.Project({50, 0, 6});
  EXPECT_FALSE(PointAtHeight(P, horizon, 0.0));
  ASSERT_TRUE(PointAtHeight(P, horizon + Eigen::Vector2d(0, 40), 0.0));
}

std::vector<double> Coefficients(int n) {
  const std::vector<double> all = {-0.28, 0.09, 1.2e-3, -8e-4, 0.02, 0.01, -0.003,
                                   0.004, 1e-3, -2e-4,  5e-4,  3e-4, 0.0,  0.0};
  return {all.begin(), all.begin() + n};
}

TEST(Distortion, MatchesOpenCvProjectPoints) {
  const Eigen::Matrix3d K = testing::Intrinsics(520, 320, 240);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> xy(-0.5, 0.5);
  for (int n : {4, 5, 8, 12, 14}) {
    const auto dist = Coefficients(n);
    std::vector<cv::Point3d> object;
    object.reserve(50);
    for (int i = 0; i < 50; ++i) object.emplace_back(xy(rng), xy(rng), 1.0);
    std::vector<cv::Point2d> image;
    cv::Mat Kcv;
    cv::eigen2cv(K, Kcv);
    cv::projectPoints(object, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), Kcv, dist, image);
    geometry::Matrix34 P;
    P << K, Eigen::Vector3d::Zero();
    const ProjectiveCamera cam(P, {640, 480}, Lens{K, dist});
    for (size_t i = 0; i < object.size(); ++i) {
      const Eigen::Vector3d X(object[i].x, object[i].y, object[i].z);
      const Eigen::Vector2d ours = *cam.ProjectObserved(X);
      EXPECT_NEAR(ours.x(), image[i].x, 1e-9) << n << " coefficients";
      EXPECT_NEAR(ours.y(), image[i].y, 1e-9) << n << " coefficients";
    }
  }
}

TEST(Distortion, UndistortInvertsDistortAndAgreesWithOpenCv) {
  const Eigen::Matrix3d K = testing::Intrinsics(520, 320, 240);
  const auto dist = Coefficients(5);
  geometry::Matrix34 P;
  P << K, Eigen::Vector3d::Zero();
  const ProjectiveCamera cam(P, {640, 480}, Lens{K, dist});
  cv::Mat Kcv;
  cv::eigen2cv(K, Kcv);
  for (int v = 0; v < 480; v += 40) {
    for (int u = 0; u < 640; u += 40) {
      const Eigen::Vector2d observed(u, v);
      const auto ideal = cam.Undistort(observed);
      ASSERT_TRUE(ideal) << u << "," << v;
      EXPECT_LT((cam.Distort(*ideal) - observed).norm(), 1e-9);
      std::vector<cv::Point2d> in = {{double(u), double(v)}}, out;
      cv::undistortPoints(
          in, out, Kcv, dist, cv::noArray(), Kcv,
          cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-14));
      EXPECT_NEAR(ideal->x(), out[0].x, 1e-6);
      EXPECT_NEAR(ideal->y(), out[0].y, 1e-6);
    }
  }
}

TEST(Distortion, NoLensIsIdentityAndBadCoefficientsAreRefused) {
  const ProjectiveCamera cam = ThesisLikeRig().left;
  EXPECT_FALSE(cam.has_distortion());
  EXPECT_EQ(cam.Distort({3, 4}), Eigen::Vector2d(3, 4));
  EXPECT_EQ(*cam.Undistort({3, 4}), Eigen::Vector2d(3, 4));
  std::string why;
  EXPECT_FALSE(CheckDistortion(std::vector<double>{1, 2, 3}, &why));
  EXPECT_NE(why.find("got 3"), std::string::npos);
  EXPECT_FALSE(CheckDistortion(std::vector<double>{0.1, NAN, 0, 0}, &why));
  std::vector<double> tilted(14, 0.0);
  tilted[12] = 0.01;
  EXPECT_FALSE(CheckDistortion(tilted, &why));
  EXPECT_THROW(ProjectiveCamera(cam.P(), {512, 480}, Lens{Eigen::Matrix3d::Identity(), {1, 2}}),
               std::invalid_argument);
  EXPECT_FALSE(UndistortNormalized({NAN, 0}, Coefficients(5)));
}

}  // namespace
}  // namespace igms::geometry
