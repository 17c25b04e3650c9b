// The viewer's orientation as platform ticks through the calibration, checked numerically
// against the platform model: commanding the ticks must turn the cameras as the head turned.
#include "control/session/orientation.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "common/geometry/platform.h"
#include "control/session/pointer.h"
#include "tests/control/session/thesis_calibration.h"

namespace igms::control {
namespace {

constexpr double kDeg = M_PI / 180.0;

// Heading (degrees, about +z, from +x) and elevation (degrees above level) of a direction.
double Heading(const Eigen::Vector3d& d) { return std::atan2(d.y(), d.x()) / kDeg; }
double Elevation(const Eigen::Vector3d& d) { return std::asin(d.z() / d.norm()) / kDeg; }

// The left camera's frame with the platform at `ticks`.
CameraFrame LeftFrameAt(const calibration::StereoCalibration& cal, const ViewerToPlatform& m,
                        const PlatformTicks& ticks) {
  const auto q = m.JointAngles(ticks);
  const geometry::Matrix34 P = geometry::CameraAtPose(cal.left.P, *cal.platform, q);
  return *CameraFrameOf(geometry::ProjectiveCamera(P, cal.left.image_size));
}

TEST(ViewerToPlatform, ThesisSignsFromTheCalibration) {
  const auto cal = testing::ThesisCalibration();
  auto m = ViewerToPlatform::Make(cal, true);
  ASSERT_TRUE(m.ok()) << m.error();
  // Pan turns left with the head; tilt is positive looking up while pitch is positive nose
  // down; roll turns with the head.
  EXPECT_EQ(m->signs(), (std::array<int, 3>{1, -1, 1}));
  EXPECT_DOUBLE_EQ(m->radians_per_tick()[0], cal.platform->joints[0].radians_per_tick);
  EXPECT_DOUBLE_EQ(m->radians_per_tick()[1], cal.platform->joints[1].radians_per_tick);
}

TEST(ViewerToPlatform, YawTurnsTheCamerasByTheSameAngle) {
  const auto cal = testing::ThesisCalibration();
  auto m = ViewerToPlatform::Make(cal, false);
  ASSERT_TRUE(m.ok()) << m.error();
  const CameraFrame zero = LeftFrameAt(cal, *m, {});
  for (double yaw : {-30.0, -10.0, 10.0, 45.0}) {
    const PlatformTicks t = m->Ticks({yaw, 7.0, 3.0});
    // Pan only (as the thesis): pitch and roll are not followed.
    EXPECT_EQ(t.pitch, 0);
    EXPECT_EQ(t.roll, 0);
    // 10 degrees of yaw is 10 / 3.684e-3 = 2714.5 ticks.
    EXPECT_NEAR(t.yaw, yaw / geometry::ThesisPanDegreesPerTick(), 0.5);
    const CameraFrame turned = LeftFrameAt(cal, *m, t);
    // Positive yaw turns left: the heading grows by the yaw, within a tick (0.0037 degree).
    EXPECT_NEAR(Heading(turned.forward) - Heading(zero.forward), yaw, 0.004) << yaw;
    EXPECT_NEAR(Elevation(turned.forward), Elevation(zero.forward), 1e-6);
  }
}

TEST(ViewerToPlatform, NoseDownPitchTiltsTheCamerasDown) {
  const auto cal = testing::ThesisCalibration();
  auto m = ViewerToPlatform::Make(cal, true);
  ASSERT_TRUE(m.ok()) << m.error();
  const CameraFrame zero = LeftFrameAt(cal, *m, {});
  for (double pitch : {-20.0, -5.0, 5.0, 20.0}) {
    const PlatformTicks t = m->Ticks({0.0, pitch, 0.0});
    // Positive pitch (nose down) is negative tilt ticks: the platform tilts up when positive.
    EXPECT_EQ(t.pitch<0, pitch> 0) << pitch;
    EXPECT_NEAR(t.pitch, -pitch / geometry::ThesisTiltDegreesPerTick(), 0.5);
    const CameraFrame tilted = LeftFrameAt(cal, *m, t);
    // The optical axis drops by the pitch, within a tick (0.0175 degree) and the left
    // camera's small offset from the roll axis (it looks 2.5 degrees up at zero).
    EXPECT_NEAR(Elevation(tilted.forward) - Elevation(zero.forward), -pitch, 0.03) << pitch;
  }
}

TEST(ViewerToPlatform, RollTurnsTheImageWithTheHead) {
  const auto cal = testing::ThesisCalibration();
  auto m = ViewerToPlatform::Make(cal, true);
  ASSERT_TRUE(m.ok()) << m.error();
  const CameraFrame zero = LeftFrameAt(cal, *m, {});
  // R = Rz Ry Rx: positive roll lifts the head's left side, so the image's right drops.
  const PlatformTicks t = m->Ticks({0.0, 0.0, 10.0});
  EXPECT_GT(t.roll, 0);
  const CameraFrame rolled = LeftFrameAt(cal, *m, t);
  EXPECT_NEAR(Elevation(rolled.right) - Elevation(zero.right), -10.0, 0.5);
}

TEST(ViewerToPlatform, AFlippedTiltAxisFlipsItsSign) {
  auto cal = testing::ThesisCalibration();
  // The pan link turned the other way: the tilt axis now points left, so positive tilt
  // looks down, and the sign must follow for nose-down to stay down.
  cal.platform->joints[0].alpha = -M_PI / 2;
  auto m = ViewerToPlatform::Make(cal, true);
  ASSERT_TRUE(m.ok()) << m.error();
  EXPECT_EQ(m->signs()[1], 1);
  const CameraFrame zero = LeftFrameAt(cal, *m, {});
  const CameraFrame tilted = LeftFrameAt(cal, *m, m->Ticks({0.0, 8.0, 0.0}));
  EXPECT_NEAR(Elevation(tilted.forward) - Elevation(zero.forward), -8.0, 0.05);
}

TEST(ViewerToPlatform, RefusesJointsThatAreNotPanTiltRoll) {
  auto cal = testing::ThesisCalibration();
  // A first joint turning about a horizontal axis cannot follow the head's yaw.
  cal.platform->world_from_base.linear() =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const auto m = ViewerToPlatform::Make(cal, false);
  ASSERT_FALSE(m.ok());
  const std::string& why = m.error();
  EXPECT_NE(why.find("joint 0 (pan)"), std::string::npos) << why;
  EXPECT_NE(why.find("the vertical"), std::string::npos) << why;
}

TEST(ViewerToPlatform, WithoutAPlatformModelTheThesisScalesAndSigns) {
  auto cal = testing::ThesisCalibration();
  cal.platform.reset();
  auto m = ViewerToPlatform::Make(cal, true);
  ASSERT_TRUE(m.ok()) << m.error();
  EXPECT_EQ(m->signs(), (std::array<int, 3>{1, -1, 1}));
  const PlatformTicks t = m->Ticks({10.0, 10.0, 10.0});
  EXPECT_EQ(t.yaw, static_cast<int32_t>(std::round(10.0 / geometry::ThesisPanDegreesPerTick())));
  EXPECT_EQ(t.pitch,
            static_cast<int32_t>(std::round(-10.0 / geometry::ThesisTiltDegreesPerTick())));
  EXPECT_EQ(t.roll, static_cast<int32_t>(std::round(10.0 / geometry::ThesisTiltDegreesPerTick())));
}

TEST(ViewerToPlatform, TicksStayInsideTheProtocol) {
  const auto cal = testing::ThesisCalibration();
  auto m = ViewerToPlatform::Make(cal, true);
  ASSERT_TRUE(m.ok()) << m.error();
  const PlatformTicks t = m->Ticks({1e9, -1e9, NAN});
  EXPECT_EQ(t.yaw, 1048575);
  EXPECT_EQ(t.pitch, 8191);
  EXPECT_EQ(t.roll, 0);
}

TEST(ViewerToPlatform, TicksAndJointAnglesRoundTrip) {
  const auto cal = testing::ThesisCalibration();
  auto m = ViewerToPlatform::Make(cal, true);
  ASSERT_TRUE(m.ok()) << m.error();
  const PlatformTicks t{2715, -286, 57};
  EXPECT_EQ(m->TicksOf(m->JointAngles(t)), t);
  EXPECT_EQ(m->JointAngles(t).size(), cal.platform->joints.size());
}

TEST(ViewerOrientation, RotationRoundTrip) {
  const ViewerOrientation o{-35.0, 12.5, 4.0};
  const ViewerOrientation back = OrientationOf(RotationOf(o));
  EXPECT_NEAR(back.yaw_deg, o.yaw_deg, 1e-9);
  EXPECT_NEAR(back.pitch_deg, o.pitch_deg, 1e-9);
  EXPECT_NEAR(back.roll_deg, o.roll_deg, 1e-9);
  // Positive pitch is nose down: the forward axis drops.
  EXPECT_LT((RotationOf({0, 10, 0}) * Eigen::Vector3d::UnitX()).z(), 0);
}

TEST(ViewerZero, ARestartedViewerContinuesWhereTheSessionWas) {
  ViewerZero zero;
  EXPECT_TRUE(zero.identity());
  // The session was at yaw 30, pitch 5; the new daemon reads its first pose as zero.
  zero.Rezero({30.0, 5.0, 0.0}, {0.0, 0.0, 0.0});
  const ViewerOrientation first = zero.Apply({0.0, 0.0, 0.0});
  EXPECT_NEAR(first.yaw_deg, 30.0, 1e-9);
  EXPECT_NEAR(first.pitch_deg, 5.0, 1e-9);
  // Turning the head 10 degrees further left turns the session's yaw with it.
  EXPECT_NEAR(zero.Apply({10.0, 0.0, 0.0}).yaw_deg, 40.0, 0.5);
}

}  // namespace
}  // namespace igms::control
