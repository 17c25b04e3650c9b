// Decomposition (thesis 3.3): round trips on synthetic cameras, agreement with the RQ
// decomposition and with OpenCV's decomposeProjectionMatrix.
#include "common/geometry/decomposition.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "tests/common/geometry/synthetic_rig.h"

namespace igms::geometry {
namespace {

TEST(ThesisDecomposition, RecoversComposedParameters) {
  std::mt19937 rng(30);
  std::uniform_real_distribution<double> angle(-0.4, 0.4), pos(-30, 30);
  for (int i = 0; i < 200; ++i) {
    ThesisDecomposition truth;
    truth.ku = -900 - 100 * angle(rng);
    truth.kv = 1100 + 100 * angle(rng);
    truth.u0 = 256 + 50 * angle(rng);
    truth.v0 = 240 + 50 * angle(rng);
    truth.center = Eigen::Vector3d(pos(rng), pos(rng), pos(rng));
    truth.theta = 1.5 + 3 * angle(rng);
    truth.phi = angle(rng);
    truth.psi = 3.0 + angle(rng) / 2;
    truth.lambda = 1;
    const Matrix34 C = ComposeThesis(truth);
    for (double scale : {1.0, -0.01}) {
      const auto d = DecomposeThesis(scale * C);
      ASSERT_TRUE(d.ok()) << d.error();
      EXPECT_NEAR(d->ku, truth.ku, 1e-6);
      EXPECT_NEAR(d->kv, truth.kv, 1e-6);
      EXPECT_NEAR(d->u0, truth.u0, 1e-7);
      EXPECT_NEAR(d->v0, truth.v0, 1e-7);
      EXPECT_LT((d->center - truth.center).norm(), 1e-8);
      EXPECT_NEAR(std::remainder(d->theta - truth.theta, 2 * M_PI), 0, 1e-9);
      EXPECT_NEAR(d->phi, truth.phi, 1e-9);
      EXPECT_NEAR(std::remainder(d->psi - truth.psi, 2 * M_PI), 0, 1e-9);
      EXPECT_NEAR(d->skew, 0, 1e-9);
      EXPECT_LT((ComposeThesis(*d) - C).norm() / C.norm(), 1e-12);
    }
  }
}

TEST(ThesisDecomposition, ReportsSkewAndRefusesDegenerateP) {
  Eigen::Matrix3d K = testing::Intrinsics(800, 256, 240);
  K(0, 1) = 0.02 * 800;  // skew of 16 px: about 0.02 rad of non-orthogonality
  const Matrix34 C = testing::LookAt(K, {0, 0, 5}, {50, 3, 2});
  const auto d = DecomposeThesis(C);
  ASSERT_TRUE(d.ok());
  EXPECT_NEAR(std::abs(d->skew), 0.02, 2e-3);
  const auto zero = DecomposeThesis(Matrix34::Zero());
  EXPECT_FALSE(zero.ok());
  EXPECT_FALSE(zero.error().empty());
  Matrix34 nan = C;
  nan(1, 1) = NAN;
  EXPECT_FALSE(DecomposeThesis(nan).ok());
  EXPECT_FALSE(DecomposeRq(nan).ok());
}

TEST(RqDecomposition, RecoversKRotationAndCentreAndMatchesOpenCv) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 100; ++i) {
    Eigen::Matrix3d K =
        testing::Intrinsics(700 + 300 * u(rng), 300 + 20 * u(rng), 220 + 20 * u(rng), 1.05);
    K(0, 1) = 3 * u(rng);
    const Eigen::Vector3d c(10 * u(rng), 10 * u(rng), 5 + u(rng));
    const Eigen::Vector3d target(60 + 10 * u(rng), 10 * u(rng), 2 * u(rng));
    const Matrix34 P = (i % 2 ? -2.5 : 0.3) * testing::LookAt(K, c, target);
    const auto d = DecomposeRq(P);
    ASSERT_TRUE(d.ok());
    EXPECT_LT((d->K - K).norm(), 1e-8);
    EXPECT_LT((d->R - testing::LookAtRotation(c, target)).norm(), 1e-10);
    EXPECT_NEAR(d->R.determinant(), 1.0, 1e-12);
    EXPECT_LT((d->center - c).norm(), 1e-9);

    cv::Mat Pcv, Kcv, Rcv, tcv;
    cv::eigen2cv(P, Pcv);
    cv::decomposeProjectionMatrix(Pcv, Kcv, Rcv, tcv);
    Eigen::Matrix3d Kocv, Rocv;
    Eigen::Vector4d tocv;
    cv::cv2eigen(Kcv, Kocv);
    cv::cv2eigen(Rcv, Rocv);
    cv::cv2eigen(tcv, tocv);
    // OpenCV leaves the signs of K's columns to its RQ; compare magnitudes and the centre.
    Kocv /= Kocv(2, 2);
    EXPECT_NEAR(std::abs(Kocv(0, 0)), d->fx(), 1e-6);
    EXPECT_NEAR(std::abs(Kocv(1, 1)), d->fy(), 1e-6);
    EXPECT_NEAR(Kocv(0, 2), d->cx(), 1e-6);
    EXPECT_NEAR(Kocv(1, 2), d->cy(), 1e-6);
    EXPECT_LT((tocv.hnormalized() - d->center).norm(), 1e-8);
  }
}

TEST(Decompositions, AgreeWithEachOther) {
  // For a skew-free camera the two decompositions describe the same camera: |ku| = fx,
  // kv = fy, (u0, v0) = (cx, cy), the thesis's y' axis is the RQ's z axis.
  const Matrix34 P =
      testing::LookAt(testing::Intrinsics(950, 310, 214, 1.25), {20.7, 3.5, 3.7}, {19, -60, 6});
  const auto t = *DecomposeThesis(P);
  const auto r = *DecomposeRq(P);
  EXPECT_NEAR(-t.ku, r.fx(), 1e-6);
  EXPECT_NEAR(t.kv, r.fy(), 1e-6);
  EXPECT_NEAR(t.u0, r.cx(), 1e-7);
  EXPECT_NEAR(t.v0, r.cy(), 1e-7);
  EXPECT_LT((t.R.row(1) - r.R.row(2)).norm(), 1e-10);
  EXPECT_LT((t.center - r.center).norm(), 1e-9);
  EXPECT_NEAR(std::remainder(t.psi, 2 * M_PI), M_PI * (t.psi > 0 ? 1 : -1), 0.1)
      << "an upright camera with ku < 0 has psi near pi";
}

}  // namespace
}  // namespace igms::geometry
