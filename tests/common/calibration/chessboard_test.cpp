// Chessboard stereo calibration on Debian's real pairs (opencv-doc: left01..right14, 13 pairs,
// 9x6 corners): beats OpenCV's own stereo_calib sample, run on the same corners in the same
// test, on both its figures; the written file loads, and triangulating a real board with it
// gives squares of the right size.
#include "common/calibration/chessboard.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Core>
#include <cstdio>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/geometry/triangulation.h"

namespace igms::calibration {
namespace {

const char* kData = "/usr/share/doc/opencv-doc/examples/data";

void Pairs(std::vector<std::string>* left, std::vector<std::string>* right) {
  for (int i = 1; i <= 14; ++i) {
    if (i == 10) continue;  // the set has no pair 10
    char name[32];
    std::snprintf(name, sizeof name, "/left%02d.jpg", i);
    left->push_back(kData + std::string(name));
    std::snprintf(name, sizeof name, "/right%02d.jpg", i);
    right->push_back(kData + std::string(name));
  }
}

TEST(Chessboard, BeatsOpenCvSampleOnRealPairs) {
  std::vector<std::string> left, right;
  Pairs(&left, &right);
  ASSERT_TRUE(std::filesystem::exists(left[0])) << "install opencv-doc (deploy/install-deps.sh)";
  ChessboardOptions options;
  std::string why;
  auto ours = CalibrateChessboard(left, right, options);
  ASSERT_TRUE(ours.ok()) << ours.error();
  options.procedure = ChessboardOptions::Procedure::kOpenCvSample;
  auto sample = CalibrateChessboard(left, right, options);
  ASSERT_TRUE(sample.ok()) << sample.error();

  EXPECT_EQ(ours->pairs_used, 13);
  EXPECT_TRUE(ours->skipped.empty());
  // The sample's procedure reproduces its published figures here...
  EXPECT_NEAR(sample->stereo_rms, 0.634, 0.005);
  EXPECT_NEAR(sample->epipolar_error, 0.445, 0.005);
  // ...and ours beats both.
  EXPECT_LT(ours->stereo_rms, sample->stereo_rms);
  EXPECT_LT(ours->epipolar_error, sample->epipolar_error);
  EXPECT_LT(ours->stereo_rms, 0.634);
  EXPECT_LT(ours->epipolar_error, 0.445);
  EXPECT_LT(ours->left_rms, 0.5);
  EXPECT_LT(ours->right_rms, 0.5);
  // The rig: right camera about 3.3 squares to the side of the left.
  EXPECT_NEAR(ours->t.norm(), 3.34, 0.1);
  EXPECT_LT(std::abs(ours->t.y()) + std::abs(ours->t.z()), 0.2);

  // The calibration file round trip, then metric triangulation of a real board.
  const auto path =
      std::filesystem::temp_directory_path() / ("igms_cb_" + std::to_string(getpid()) + ".yaml");
  ASSERT_TRUE(SaveCalibration(ours->calibration, path.string(), &why)) << why;
  auto loaded = LoadCalibration(path.string());
  std::filesystem::remove(path);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  const auto L = loaded->left.Camera(), R = loaded->right.Camera();
  EXPECT_TRUE(L.has_distortion());
  std::vector<cv::Point2f> cl, cr;
  ASSERT_TRUE(cv::findChessboardCorners(cv::imread(left[0], cv::IMREAD_GRAYSCALE), {9, 6}, cl));
  ASSERT_TRUE(cv::findChessboardCorners(cv::imread(right[0], cv::IMREAD_GRAYSCALE), {9, 6}, cr));
  std::vector<Eigen::Vector3d> pts;
  for (size_t i = 0; i < cl.size(); ++i) {
    const auto ul = L.Undistort({cl[i].x, cl[i].y}), ur = R.Undistort({cr[i].x, cr[i].y});
    ASSERT_TRUE(ul && ur);
    auto t = geometry::Triangulate(L.P(), R.P(), *ul, *ur, geometry::TriangulationMethod::kRefined);
    ASSERT_TRUE(t.ok());
    EXPECT_LT(t->rms_error, 1.0);
    pts.push_back(t->point);
  }
  double sum = 0;
  int n = 0;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c + 1 < 9; ++c) {
      sum += (pts[r * 9 + c + 1] - pts[r * 9 + c]).norm();
      ++n;
    }
  }
  EXPECT_NEAR(sum / n, 1.0, 0.02) << "adjacent corners are one square apart";
}

TEST(Chessboard, RefusesBadInput) {
  std::vector<std::string> left, right;
  Pairs(&left, &right);
  std::string why;
  why = CalibrateChessboard(left, {right[0]}, {}).error();
  EXPECT_NE(why, "");
  EXPECT_NE(why.find("13 left images but 1 right"), std::string::npos);
  why = CalibrateChessboard({"/nonexistent.jpg"}, {right[0]}, {}).error();
  EXPECT_NE(why, "");
  EXPECT_NE(why.find("cannot read"), std::string::npos);
  ChessboardOptions square;
  square.cols = square.rows = 6;
  why = CalibrateChessboard(left, right, square).error();
  EXPECT_NE(why, "");
  why = CalibrateChessboard({left[0], left[1]}, {right[0], right[1]}, {.cols = 5, .rows = 12})
            .error();
  EXPECT_NE(why, "");
  EXPECT_NE(why.find("at least 3"), std::string::npos);
}

}  // namespace
}  // namespace igms::calibration
