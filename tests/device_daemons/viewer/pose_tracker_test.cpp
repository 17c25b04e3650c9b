#include "device_daemons/viewer/pose_tracker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace igms::devices {
namespace {

constexpr double kInch = 0.0254;

TEST(PoseTracker, YprRoundTripsAndFollowsItsConvention) {
  // Yaw turns x (forward) towards y (left); positive pitch puts the nose down.
  EXPECT_TRUE(
      (RotationFromYpr(90, 0, 0) * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_TRUE(
      (RotationFromYpr(0, 90, 0) * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(
      (RotationFromYpr(0, 0, 90) * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ()));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> yaw(-180, 180), pitch(-89, 89);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d ypr(yaw(rng), pitch(rng), yaw(rng));
    const Eigen::Vector3d back = YprFromRotation(RotationFromYpr(ypr[0], ypr[1], ypr[2]));
    EXPECT_LT((back - ypr).norm(), 1e-9) << ypr.transpose() << " -> " << back.transpose();
  }
  // Gimbal lock: the same rotation comes back, with roll 0.
  const Eigen::Matrix3d locked = RotationFromYpr(30, 90, 20);
  const Eigen::Vector3d ypr = YprFromRotation(locked);
  EXPECT_DOUBLE_EQ(ypr[2], 0.0);
  EXPECT_TRUE(RotationFromYpr(ypr[0], ypr[1], ypr[2]).isApprox(locked, 1e-9));
}

TEST(PoseTracker, ReportsThePoseRelativeToPowerUpAtTheBoomsResolution) {
  PoseTrackerOptions o;
  // Powered up 20 in above the table origin, looking along -y (yaw -90).
  o.site_from_power_up.translate(Eigen::Vector3d(10, 0, 20));
  o.site_from_power_up.rotate(RotationFromYpr(-90, 0, 0));
  PoseTracker tracker(o);
  // At the power-up pose: zero.
  TrackerReading r = tracker.Read(o.site_from_power_up);
  EXPECT_LT(r.position_m.norm() + r.ypr_deg.norm(), 1e-12);
  // Stepping 4 in along the site's -y is 4 in forward for the head; turning to look along
  // -x is a yaw of -90 from there.
  Eigen::Isometry3d head = Eigen::Isometry3d::Identity();
  head.translate(Eigen::Vector3d(10, -4, 20));
  head.rotate(RotationFromYpr(180, 10, 0));
  r = tracker.Read(head);
  EXPECT_NEAR(r.position_m.x(), 4 * kInch, 0.00025);
  EXPECT_NEAR(r.position_m.y(), 0, 1e-12);
  EXPECT_NEAR(r.ypr_deg[0], -90, 360.0 / 8192 / 2);
  EXPECT_NEAR(r.ypr_deg[1], 10, 360.0 / 8192 / 2);
  EXPECT_FALSE(r.clamped);
  // Quantised: whole steps of 0.5 mm and 360/8192 degree.
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(r.position_m[i] / 0.0005, std::round(r.position_m[i] / 0.0005), 1e-6);
    EXPECT_NEAR(r.ypr_deg[i] / (360.0 / 8192), std::round(r.ypr_deg[i] / (360.0 / 8192)), 1e-6);
  }
  // Back to the site: within the resolution.
  const Eigen::Isometry3d back = tracker.HeadInSite(r);
  EXPECT_LT((back.translation() - head.translation()).norm(), 0.001 / kInch);
  EXPECT_LT((back.linear() - head.linear()).norm(), 0.002);
}

TEST(PoseTracker, ClampsToItsRangeAndRejectsBadOptions) {
  PoseTracker tracker;
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translate(Eigen::Vector3d(2.0 / kInch, -0.5 / kInch, 0));
  const TrackerReading r = tracker.Read(far);
  EXPECT_TRUE(r.clamped);
  EXPECT_DOUBLE_EQ(r.position_m.x(), 1.0235);
  EXPECT_NEAR(r.position_m.y(), -0.5, 1e-12);
  PoseTrackerOptions bad;
  bad.position_step_m = -1;
  std::string error;
  EXPECT_FALSE(bad.Check(&error));
  EXPECT_NE(error.find("position_step_m"), std::string::npos);
  bad = {};
  bad.site_from_power_up.linear() *= 2;
  EXPECT_FALSE(bad.Check(&error));
  EXPECT_THROW(PoseTracker{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace igms::devices
