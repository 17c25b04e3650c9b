#include "common/calibration/chessboard.h"

#include <Eigen/Core>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/base/result.h"

namespace igms::calibration {
namespace {

using Corners = std::vector<cv::Point2f>;

std::optional<Corners> FindCorners(const cv::Mat& gray, cv::Size board) {
  Corners corners;
  for (int scale = 1; scale <= 2; ++scale) {
    cv::Mat img = gray;
    if (scale > 1) cv::resize(gray, img, cv::Size(), scale, scale, cv::INTER_LINEAR_EXACT);
    if (cv::findChessboardCorners(img, board, corners,
                                  cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE)) {
      for (auto& c : corners) c *= 1.0f / static_cast<float>(scale);
      cv::cornerSubPix(gray, corners, cv::Size(11, 11), cv::Size(-1, -1),
                       cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 30, 0.01));
      return corners;
    }
  }
  return std::nullopt;
}

std::vector<cv::Point3f> BoardPoints(const ChessboardOptions& o) {
  std::vector<cv::Point3f> pts;
  for (int r = 0; r < o.rows; ++r) {
    for (int c = 0; c < o.cols; ++c) {
      pts.emplace_back(static_cast<float>(c * o.square), static_cast<float>(r * o.square), 0.f);
    }
  }
  return pts;
}

double EpipolarErrorLikeSample(const std::vector<Corners>& left, const std::vector<Corners>& right,
                               const cv::Mat K[2], const cv::Mat dist[2], const cv::Mat& F) {
  double err = 0;
  size_t npoints = 0;
  for (size_t i = 0; i < left.size(); ++i) {
    Corners pts[2] = {left[i], right[i]};
    std::vector<cv::Vec3f> lines[2];
    for (int k = 0; k < 2; ++k) {
      cv::undistortPoints(Corners(pts[k]), pts[k], K[k], dist[k], cv::noArray(), K[k]);
      cv::computeCorrespondEpilines(pts[k], k + 1, F, lines[k]);
    }
    for (size_t j = 0; j < pts[0].size(); ++j) {
      err +=
          std::abs(pts[0][j].x * lines[1][j][0] + pts[0][j].y * lines[1][j][1] + lines[1][j][2]) +
          std::abs(pts[1][j].x * lines[0][j][0] + pts[1][j].y * lines[0][j][1] + lines[0][j][2]);
    }
    npoints += pts[0].size();
  }
  return err / static_cast<double>(npoints);
}

CameraCalibration ToCamera(const cv::Mat& K, const cv::Mat& dist, const Eigen::Matrix3d& R,
                           const Eigen::Vector3d& t, cv::Size size) {
  CameraCalibration c;
  Eigen::Matrix3d Ke;
  cv::cv2eigen(K, Ke);
  c.K = Ke;
  c.dist.assign(dist.begin<double>(), dist.end<double>());
  geometry::Matrix34 Rt;
  Rt << R, t;
  c.P = Ke * Rt;
  c.image_size = {size.width, size.height};
  return c;
}

}  // namespace

bool ChessboardOptions::Check(std::string* error) const {
  if (cols < 2 || rows < 2) return Fail(error, "the board needs at least 2x2 inner corners");
  if (cols == rows) return Fail(error, "a square board is ambiguous: use different counts");
  if (!(square > 0) || !std::isfinite(square)) return Fail(error, "square size must be > 0");
  return true;
}

Result<ChessboardResult> CalibrateChessboard(const std::vector<std::string>& left,
                                             const std::vector<std::string>& right,
                                             const ChessboardOptions& options,
                                             const Progress& progress) {
  if (std::string why; !options.Check(&why)) return ErrorMessage{why};
  if (left.size() != right.size()) {
    return ErrorMessage{"got " + std::to_string(left.size()) + " left images but " +
                        std::to_string(right.size()) + " right images"};
  }
  const cv::Size board(options.cols, options.rows);
  ChessboardResult result;
  std::vector<Corners> corners[2];
  cv::Size size;
  for (size_t i = 0; i < left.size(); ++i) {
    if (progress) {
      progress("corners " + std::to_string(i + 1) + "/" + std::to_string(left.size()) + ": " +
               left[i] + ", " + right[i]);
    }
    std::optional<Corners> found[2];
    const std::string* paths[2] = {&left[i], &right[i]};
    for (int k = 0; k < 2; ++k) {
      const cv::Mat img = cv::imread(*paths[k], cv::IMREAD_GRAYSCALE);
      if (img.empty()) {
        return ErrorMessage{*paths[k] + ": cannot read the image"};
      }
      if (size.area() == 0) size = img.size();
      if (img.size() != size) {
        return ErrorMessage{*paths[k] + ": image size differs from the first image's"};
      }
      found[k] = FindCorners(img, board);
    }
    if (!found[0] || !found[1]) {
      result.skipped.push_back(*paths[found[0] ? 1 : 0] + ": no " + std::to_string(options.cols) +
                               "x" + std::to_string(options.rows) + " board found");
      continue;
    }
    corners[0].push_back(*found[0]);
    corners[1].push_back(*found[1]);
  }
  result.pairs_used = static_cast<int>(corners[0].size());
  if (result.pairs_used < 3) {
    return ErrorMessage{"only " + std::to_string(result.pairs_used) +
                        " pairs show the board in both images; at least 3 are needed"};
  }
  const std::vector<std::vector<cv::Point3f>> object(result.pairs_used, BoardPoints(options));
  cv::Mat K[2], dist[2];
  using Procedure = ChessboardOptions::Procedure;
  int flags = 0;
  if (options.procedure == Procedure::kOpenCvSample) {
    for (int k = 0; k < 2; ++k) K[k] = cv::initCameraMatrix2D(object, corners[k], size, 0);
    flags = cv::CALIB_FIX_ASPECT_RATIO | cv::CALIB_ZERO_TANGENT_DIST |
            cv::CALIB_USE_INTRINSIC_GUESS | cv::CALIB_SAME_FOCAL_LENGTH | cv::CALIB_RATIONAL_MODEL |
            cv::CALIB_FIX_K3 | cv::CALIB_FIX_K4 | cv::CALIB_FIX_K5;
  } else {
    for (int k = 0; k < 2; ++k) {
      if (progress) progress(std::string("calibrating the ") + (k ? "right" : "left") + " camera");
      std::vector<cv::Mat> rvecs, tvecs;
      const double rms = cv::calibrateCamera(object, corners[k], size, K[k], dist[k], rvecs, tvecs);
      (k ? result.right_rms : result.left_rms) = rms;
    }
    flags = options.procedure == Procedure::kJoint ? cv::CALIB_USE_INTRINSIC_GUESS
                                                   : cv::CALIB_FIX_INTRINSIC;
  }
  if (progress) progress("calibrating the pair");
  cv::Mat R, T, E, F;
  result.stereo_rms = cv::stereoCalibrate(
      object, corners[0], corners[1], K[0], dist[0], K[1], dist[1], size, R, T, E, F, flags,
      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100,
                       options.procedure == Procedure::kOpenCvSample ? 1e-5 : 1e-6));
  for (int k = 0; k < 2; ++k) dist[k] = dist[k].reshape(1, 1);
  result.epipolar_error = EpipolarErrorLikeSample(corners[0], corners[1], K, dist, F);
  result.epipolar_error_per_image = result.epipolar_error / 2;
  cv::cv2eigen(R, result.R);
  cv::cv2eigen(T, result.t);
  result.calibration.left =
      ToCamera(K[0], dist[0], Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), size);
  result.calibration.right = ToCamera(K[1], dist[1], result.R, result.t, size);
  std::string why;
  if (!ValidateCalibration(result.calibration, &why)) {
    return ErrorMessage{"calibration came out invalid: " + why};
  }
  return result;
}

}  // namespace igms::calibration
