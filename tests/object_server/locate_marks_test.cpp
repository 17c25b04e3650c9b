// The marks as a bound on the locator's fit (object_server/locate_steps.h): the operator puts
// them just outside the object's outline (Cooke, section 3.8), so a start that leaves much of
// them empty is stretched to fill them.
#include <gtest/gtest.h>

#include <Eigen/Core>

#include "object_server/locate_steps.h"
#include "tests/object_server/rig_camera.h"

namespace igms::object {
namespace {

using testing::RigCamera;

// An upright pipe of radius 1 from z = -4 to 4 at x = 0, 40 in in front of the left camera
// (10 px to the inch there), marked 0.5 in outside its outline.
class StretchToMarks : public ::testing::Test {
 protected:
  void SetUp() override {
    // Its outline spans u 147.5..167.5 and v 55.5..135.5 in the left image.
    const float u0 = 142.5F, u1 = 172.5F, v0 = 50.5F, v1 = 140.5F;
    marks_.hull = {{u0, v0}, {u0, v1}, {u1, v1}, {u1, v0}};
    marks_.depth = 39;
  }
  // A start of radius 1 on the pipe's axis from z = bottom to top.
  static Eigen::VectorXd Start(double bottom, double top) {
    Eigen::VectorXd x(7);
    x << 0, 40, bottom, 0, 40, top, 1;
    return x;
  }
  const geometry::ProjectiveCamera camera_ = RigCamera(-3);
  MarkedRegion marks_;
};

TEST_F(StretchToMarks, AStartOnTheUpperHalfReachesDownToTheMarks) {
  // The boundary stopped where the pipe's background changed: a start from z = 0 to 4.
  const auto stretched = CylinderStretchedToMarks(Start(0, 4), marks_, camera_, 0.3);
  ASSERT_TRUE(stretched.has_value());
  // The marks' rectangle shrunk by 0.3 in and the radius (13 px): v 63.5..127.5, z -3.2..3.2,
  // at the start's own depth and position across the view.
  const Eigen::Vector3d low = stretched->segment<3>(0), high = stretched->segment<3>(3);
  EXPECT_NEAR(std::min(low.z(), high.z()), -3.2, 0.05);
  EXPECT_NEAR(std::max(low.z(), high.z()), 3.2, 0.05);
  for (const auto& end : {low, high}) {
    EXPECT_NEAR(end.x(), 0, 1e-6);
    EXPECT_NEAR(end.y(), 40, 1e-6);
  }
  EXPECT_EQ((*stretched)[6], 1);
}

TEST_F(StretchToMarks, AStartThatFillsTheMarksOrLiesOutsideThemIsLeft) {
  // Already filling them: nothing to stretch.
  EXPECT_FALSE(CylinderStretchedToMarks(Start(-3.2, 3.2), marks_, camera_, 0.3).has_value());
  // Its middle outside the marked rectangle: it is not this object's start.
  Eigen::VectorXd aside = Start(0, 4);
  aside[0] = aside[3] = 3;  // 30 px to the right
  EXPECT_FALSE(CylinderStretchedToMarks(aside, marks_, camera_, 0.3).has_value());
  // No marks.
  EXPECT_FALSE(CylinderStretchedToMarks(Start(0, 4), MarkedRegion{}, camera_, 0.3).has_value());
}

}  // namespace
}  // namespace igms::object
