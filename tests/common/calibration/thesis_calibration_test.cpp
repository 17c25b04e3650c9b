// The thesis's calibration in code is the lab's calibration file, and holds the matrices the
// thesis printed (Cooke, section 4.2, equations 4.1 and 4.2) to the last bit.
#include "common/calibration/thesis_calibration.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace igms::calibration {
namespace {

std::string ThesisFilePath() {
  const char* dir = std::getenv("IGMS_SOURCE_DIR");
  return std::string(dir ? dir : ".") + "/common/calibration/data/thesis_calibration.yaml";
}

TEST(ThesisCalibration, IsTheLabFileAsBuiltIn) {
  std::ifstream in(ThesisFilePath());
  ASSERT_TRUE(in) << ThesisFilePath();
  std::ostringstream text;
  text << in.rdbuf();
  EXPECT_EQ(ThesisCalibrationYaml(), text.str());

  const auto file = LoadCalibration(ThesisFilePath());
  ASSERT_TRUE(file.ok()) << file.error();
  const StereoCalibration& built_in = ThesisCalibration();
  EXPECT_EQ(built_in.left.P, file->left.P);
  EXPECT_EQ(built_in.right.P, file->right.P);
  ASSERT_TRUE(built_in.platform && built_in.ranger);
  EXPECT_EQ(built_in.platform->world_from_base.matrix(), file->platform->world_from_base.matrix());
  EXPECT_EQ(built_in.ranger->axis, file->ranger->axis);
}

TEST(ThesisCalibration, HoldsThePrintedMatrices) {
  geometry::Matrix34 left, right;
  left << -232.71, -64.35, 4.45, 5031.32, -5.22, -63.50, -285.65, 1379.56, -0.01, -0.24, 0.01, 1.00;
  right << -214.44, -60.906, 4.84, 3844.42, -4.93, -58.97, -261.44, 1294.73, -0.01, -0.22, 0.01,
      1.00;
  // Exactly: the simulated site and the reference figures were computed from these literals.
  EXPECT_EQ(ThesisCalibration().left.P, left);
  EXPECT_EQ(ThesisCalibration().right.P, right);
  EXPECT_EQ(ThesisCalibration().left.image_size.width, 512);
  EXPECT_EQ(ThesisCalibration().right.image_size.height, 480);
  EXPECT_FALSE(ThesisCalibration().left.K);
}

}  // namespace
}  // namespace igms::calibration
