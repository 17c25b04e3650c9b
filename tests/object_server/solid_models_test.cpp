// The solids' geometry (object_server/solid_models.h): how much of one solid lies inside
// another, and the points of a pipe's outline.
#include "object_server/solid_models.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <vector>

namespace igms::object {
namespace {

TEST(SolidModels, ShareInsideIsTheShareOfOneSolidsVolumeInsideTheOther) {
  Eigen::VectorXd block(7), half(7), turned(7), pipe(7), resting(7);
  block << 0, 0, 1, 2, 2, 2, 0;           // x, y in [-1, 1], z in [0, 2]
  half << 1, 0, 1, 2, 2, 2, 0;            // its half x > 0 overlaps the block
  turned << 0, 0, 1, 2, 2, 2, M_PI / 4;   // the block turned an eighth of a turn
  pipe << -0.5, 0, 1, 0.5, 0, 1, 0.25;    // wholly inside the block
  resting << -3, 0, 2.5, 3, 0, 2.5, 0.5;  // lying on the block's top
  EXPECT_DOUBLE_EQ(ShareInside(false, block, false, block), 1.0);
  EXPECT_DOUBLE_EQ(ShareInside(false, half, false, block), 0.5);
  EXPECT_DOUBLE_EQ(ShareInside(true, pipe, false, block), 1.0);
  // Of the block around it, only the pipe's own volume lies inside the pipe.
  EXPECT_NEAR(ShareInside(false, block, true, pipe), M_PI * 0.25 * 0.25 * 1 / 8, 0.01);
  // The turned block's corners stick out: the octagon the two sections share is
  // 2 (sqrt 2 - 1), 83%, of either.
  EXPECT_NEAR(ShareInside(false, turned, false, block), 2 * (std::sqrt(2.0) - 1), 0.03);
  // A pipe resting on a block shares no volume with it.
  EXPECT_EQ(ShareInside(true, resting, false, block), 0.0);
  EXPECT_EQ(ShareInside(false, block, true, resting), 0.0);
  EXPECT_TRUE(InsideSolid(true, pipe, Eigen::Vector3d(0, 0.2, 1)));
  EXPECT_FALSE(InsideSolid(true, pipe, Eigen::Vector3d(0, 0.3, 1)));
  EXPECT_FALSE(InsideSolid(true, pipe, Eigen::Vector3d(0.6, 0, 1)));
}

// The outline of a pipe moves as little as its axis does, whichever way the axis leans: near the
// vertical the rim's points once turned by up to 180 degrees round it for a tilt of 1e-9 in,
// and an upright pipe's radius came out of the fit with a sigma of about 100 in.
TEST(SolidModels, ACylindersRimMovesSmoothlyWithTheAxis) {
  for (const Eigen::Vector3d& axis :
       {Eigen::Vector3d(0, 0, 10), Eigen::Vector3d(0, 0, -10), Eigen::Vector3d(10, 0, 0),
        Eigen::Vector3d(3, 4, 0), Eigen::Vector3d(1, 1, 8), Eigen::Vector3d(6, 0, 6)}) {
    Eigen::VectorXd x(7);
    x << 1, 2, 3, Eigen::Vector3d(1, 2, 3) + axis, 0.5;
    const std::vector<Eigen::Vector3d> at = CylinderOutline(x);
    for (const Eigen::Vector3d& nudge : {Eigen::Vector3d(1e-6, 0, 0), Eigen::Vector3d(0, 1e-6, 0),
                                         Eigen::Vector3d(-1e-6, 1e-6, 0)}) {
      Eigen::VectorXd y = x;
      y.segment<3>(3) += nudge;
      const std::vector<Eigen::Vector3d> moved = CylinderOutline(y);
      ASSERT_EQ(moved.size(), at.size());
      double most = 0;
      for (size_t i = 0; i < at.size(); ++i) most = std::max(most, (moved[i] - at[i]).norm());
      EXPECT_LT(most, 1e-5) << "axis " << axis.transpose() << ", nudge " << nudge.transpose();
    }
    // Every point lies on the rims: at the radius from the axis, in an end's plane.
    const Eigen::Vector3d w = axis.normalized();
    for (size_t i = 0; i < at.size(); ++i) {
      const Eigen::Vector3d end = i < at.size() / 2 ? x.head<3>() : x.segment<3>(3);
      const Eigen::Vector3d d = at[i] - end;
      EXPECT_NEAR(d.dot(w), 0, 1e-9);
      EXPECT_NEAR(d.norm(), 0.5, 1e-9);
    }
  }
}

}  // namespace
}  // namespace igms::object
