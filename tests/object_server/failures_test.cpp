// Each failure reason of the locator, triggered on purpose on a rendered scene.
#include <gtest/gtest.h>

#include <cmath>

#include "common/sim/marks.h"
#include "common/sim/renderer.h"
#include "common/sim/testbed.h"
#include "object_server/locate.h"
#include "object_server/result_json.h"

namespace igms::object {
namespace {

class Failures : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = site::RandomTestbedScene(42);
    images_ = site::RenderStereo(scene_);
    for (size_t i = 0; i < scene_.objects.size(); ++i)
      if (std::holds_alternative<site::Cylinder>(scene_.objects[i].shape)) {
        object_ = i;
        break;
      }
    input_.type = SolidType::kCylinder;
    input_.marks = *site::GenerateMarks(scene_.objects[object_].shape, scene_.cameras.left, 7);
    input_.left = images_.left;
    input_.right = images_.right;
    input_.left_camera = scene_.cameras.left;
    input_.right_camera = scene_.cameras.right;
  }
  LocateResult Run() { return Locate(input_); }
  site::Scene scene_;
  site::StereoImages images_;
  size_t object_ = 0;
  LocateInput input_;
};

TEST_F(Failures, GoodMarksFindTheCylinder) {
  const LocateResult r = Run();
  ASSERT_TRUE(r.found) << r.detail;
  const auto& truth = std::get<site::Cylinder>(scene_.objects[object_].shape);
  EXPECT_NEAR(r.cylinder.radius, truth.radius, 0.05);
  EXPECT_NEAR(r.cylinder.height, truth.height, 0.2);
  EXPECT_LT((r.cylinder.center - truth.center).norm(), 0.5);
  EXPECT_GT(r.cylinder.radius_sigma, 0);
  EXPECT_LT(r.cylinder.radius_sigma, 0.05);
}

TEST_F(Failures, NanMarkIsBadInput) {
  input_.marks[2].x() = std::nan("");
  EXPECT_EQ(Run().reason, Failure::kBadInput);
}

TEST_F(Failures, MissingImageIsBadInput) {
  input_.right = cv::Mat();
  EXPECT_EQ(Run().reason, Failure::kBadInput);
  input_.right = cv::Mat(100, 100, CV_8U, cv::Scalar(0));
  EXPECT_EQ(Run().reason, Failure::kBadInput);
}

TEST_F(Failures, CoincidentMarksAreDegenerate) {
  for (auto& m : input_.marks) m = input_.marks[0];
  const auto r = Run();
  EXPECT_EQ(r.reason, Failure::kMarksDegenerate) << r.detail;
}

TEST_F(Failures, MarkBehindTheCamera) {
  input_.marks[1] = scene_.cameras.left.Center() + Eigen::Vector3d(0, 10, 0);  // cameras look along -y
  EXPECT_EQ(Run().reason, Failure::kMarksBehindCamera);
}

TEST_F(Failures, MarksOutsideTheImage) {
  for (auto& m : input_.marks) m.x() += 200;  // far to the side
  EXPECT_EQ(Run().reason, Failure::kMarksOutsideImage);
}

TEST_F(Failures, NoEdgeInAnEmptyRegion) {
  // Above the far end of the table the view is the uniform dark background.
  const Eigen::Vector3d c = scene_.cameras.left.Center();
  const double y = c.y() - 200, z = 30;
  input_.marks = {Eigen::Vector3d(c.x() - 3, y, z + 3), Eigen::Vector3d(c.x() + 3, y, z + 3),
                  Eigen::Vector3d(c.x() + 3, y, z - 3), Eigen::Vector3d(c.x() - 3, y, z - 3)};
  const auto r = Run();
  EXPECT_EQ(r.reason, Failure::kNoEdgeNearMarks) << r.detail;
  EXPECT_FALSE(r.detail.empty());
}

TEST_F(Failures, RightImageWithoutTheObjectHasNoMatch) {
  site::Scene without = scene_;
  without.objects.erase(without.objects.begin() + object_);
  input_.right = site::Render(without, without.cameras.right, 1);
  const auto r = Run();
  EXPECT_FALSE(r.found);
  EXPECT_TRUE(r.reason == Failure::kMatchOverThreshold || r.reason == Failure::kLeftRightInconsistent)
      << FailureName(r.reason) << ": " << r.detail;
}

TEST_F(Failures, WrongDepthMarksAreInconsistentOrUnmatched) {
  // Marks 12 in behind the object: its match lies outside the +/- 3 in search.
  const Eigen::Vector3d c = scene_.cameras.left.Center();
  for (auto& m : input_.marks) m = c + (m - c) * ((m - c).norm() + 12) / (m - c).norm();
  const auto r = Run();
  EXPECT_FALSE(r.found);
  EXPECT_TRUE(r.reason == Failure::kMatchOverThreshold || r.reason == Failure::kLeftRightInconsistent)
      << FailureName(r.reason) << ": " << r.detail;
}

TEST_F(Failures, JsonCarriesTheReason) {
  input_.marks[0].y() = std::numeric_limits<double>::infinity();
  const std::string json = ResultToJson(Run());
  EXPECT_NE(json.find("\"found\": false"), std::string::npos) << json;
  EXPECT_NE(json.find("\"reason\": \"bad_input\""), std::string::npos) << json;
}

}  // namespace
}  // namespace igms::object
