#include "object_server/calibration_file.h"

#include <Eigen/Dense>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>

namespace igms::object {
namespace {

std::optional<geometry::ProjectiveCamera> ReadCamera(const cv::FileNode& node, const std::string& name,
                                                     std::string& error) {
  if (node.empty() || !node.isMap()) {
    error = "missing map '" + name + "'";
    return std::nullopt;
  }
  cv::Mat P;
  node["P"] >> P;
  if (P.rows != 3 || P.cols != 4) {
    error = name + ".P: expected a 3x4 matrix";
    return std::nullopt;
  }
  P.convertTo(P, CV_64F);
  std::vector<int> size;
  node["image_size"] >> size;
  if (size.size() != 2 || size[0] <= 0 || size[1] <= 0 || size[0] > 16384 || size[1] > 16384) {
    error = name + ".image_size: expected [width, height]";
    return std::nullopt;
  }
  geometry::Matrix34 m;
  cv::cv2eigen(P, m);
  if (!m.allFinite() || std::abs(m.leftCols<3>().determinant()) < 1e-12) {
    error = name + ".P: not a finite camera matrix with an invertible left 3x3 block";
    return std::nullopt;
  }
  return geometry::ProjectiveCamera(m, {size[0], size[1]});
}

}  // namespace

CalibrationLoad LoadStereoCalibration(const std::string& path) {
  CalibrationLoad out;
  try {
    cv::FileStorage fs(path, cv::FileStorage::READ);
    if (!fs.isOpened()) {
      out.error = "cannot open calibration file " + path;
      return out;
    }
    std::string error;
    auto left = ReadCamera(fs["left"], "left", error);
    auto right = left ? ReadCamera(fs["right"], "right", error) : std::nullopt;
    if (!left || !right) {
      out.error = path + ": " + error;
      return out;
    }
    out.calibration = StereoCalibration{*left, *right};
  } catch (const cv::Exception& e) {
    out.error = path + ": not a readable calibration file (" + e.msg + ")";
  }
  return out;
}

bool SaveStereoCalibration(const std::string& path, const StereoCalibration& c) {
  cv::FileStorage fs(path, cv::FileStorage::WRITE);
  if (!fs.isOpened()) return false;
  for (auto [name, cam] : {std::pair{"left", &c.left}, std::pair{"right", &c.right}}) {
    cv::Mat P;
    cv::eigen2cv(Eigen::Matrix<double, 3, 4>(cam->P()), P);
    fs << name << "{" << "P" << P << "image_size" << std::vector<int>{cam->image_size().width, cam->image_size().height}
       << "}";
  }
  return true;
}

}  // namespace igms::object
