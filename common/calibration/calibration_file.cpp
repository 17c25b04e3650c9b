#include "common/calibration/calibration_file.h"

#include <Eigen/Dense>
#include <cmath>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>
#include <stdexcept>

#include "common/base/result.h"
#include "common/geometry/distortion.h"

namespace igms::calibration {
namespace {

// Every reader returns false after writing "key: why" into *error.
bool ReadMatrix(const cv::FileNode& node, const std::string& key, int rows, int cols,
                Eigen::MatrixXd* out, std::string* error) {
  if (node.empty() || node.isNone()) return Fail(error, key + ": missing");
  cv::Mat m;
  if (node.isSeq()) {  // a plain list: read as a column
    std::vector<double> values;
    for (const auto& item : node) {
      if (!item.isReal() && !item.isInt()) return Fail(error, key + ": list holds a non-number");
      values.push_back(static_cast<double>(item));
    }
    m = cv::Mat(values, true);
  } else if (node.isMap()) {
    try {
      node >> m;
    } catch (const cv::Exception& e) {
      return Fail(error, key + ": not a readable !!opencv-matrix (" + e.err + ")");
    }
  } else {
    return Fail(error, key + ": expected a matrix");
  }
  if (m.empty()) return Fail(error, key + ": empty or malformed matrix");
  if (m.channels() != 1) return Fail(error, key + ": matrix must have one channel");
  m.convertTo(m, CV_64F);
  if (cols < 0) {  // a vector of any length, either orientation
    if (m.rows != 1 && m.cols != 1) {
      return Fail(error, key + ": expected a vector, got " + std::to_string(m.rows) + "x" +
                             std::to_string(m.cols));
    }
    m = m.reshape(1, static_cast<int>(m.total()));
  } else if (m.rows != rows || m.cols != cols) {
    return Fail(error, key + ": expected a " + std::to_string(rows) + "x" + std::to_string(cols) +
                           " matrix, got " + std::to_string(m.rows) + "x" + std::to_string(m.cols));
  }
  cv::cv2eigen(m, *out);
  if (!out->allFinite()) return Fail(error, key + ": matrix holds a non-finite value");
  return true;
}

bool ReadVector3(const cv::FileNode& node, const std::string& key, Eigen::Vector3d* out,
                 std::string* error) {
  Eigen::MatrixXd m;
  if (!ReadMatrix(node, key, 3, -1, &m, error)) return false;
  if (m.size() != 3) {
    return Fail(error, key + ": expected 3 numbers, got " + std::to_string(m.size()));
  }
  *out = Eigen::Map<Eigen::Vector3d>(m.data());
  return true;
}

bool ReadNumber(const cv::FileNode& node, const std::string& key, double* out, std::string* error) {
  if (node.empty() || node.isNone()) return Fail(error, key + ": missing");
  if (!node.isReal() && !node.isInt()) return Fail(error, key + ": expected a number");
  *out = static_cast<double>(node);
  if (!std::isfinite(*out)) return Fail(error, key + ": not finite");
  return true;
}

bool ReadCamera(const cv::FileNode& node, const std::string& key, CameraCalibration* camera,
                std::string* error) {
  if (node.empty() || node.isNone()) return Fail(error, key + ": missing");
  if (!node.isMap()) return Fail(error, key + ": expected a map with P and image_size");
  Eigen::MatrixXd m;
  if (!ReadMatrix(node["P"], key + ".P", 3, 4, &m, error)) return false;
  camera->P = m;
  const cv::FileNode size = node["image_size"];
  if (size.empty() || size.isNone()) return Fail(error, key + ".image_size: missing");
  if (!size.isSeq() || size.size() != 2 || !size[0].isInt() || !size[1].isInt()) {
    return Fail(error, key + ".image_size: expected [width, height] as two integers");
  }
  camera->image_size = {static_cast<int>(size[0]), static_cast<int>(size[1])};
  if (!node["K"].empty() && !node["K"].isNone()) {
    if (!ReadMatrix(node["K"], key + ".K", 3, 3, &m, error)) return false;
    camera->K = Eigen::Matrix3d(m);
  }
  if (!node["dist"].empty() && !node["dist"].isNone()) {
    if (!ReadMatrix(node["dist"], key + ".dist", 0, -1, &m, error)) return false;
    camera->dist.assign(m.data(), m.data() + m.size());
  }
  return true;
}

bool ReadPlatform(const cv::FileNode& node, geometry::PlatformModel* model, std::string* error) {
  if (!node.isMap()) return Fail(error, "platform: expected a map");
  Eigen::MatrixXd m;
  if (!ReadMatrix(node["world_from_base"], "platform.world_from_base", 4, 4, &m, error)) {
    return false;
  }
  model->world_from_base.matrix() = m;
  const cv::FileNode joints = node["joints"];
  if (!joints.isSeq()) return Fail(error, "platform.joints: expected a list of joints");
  for (int i = 0; i < static_cast<int>(joints.size()); ++i) {
    const cv::FileNode j = joints[i];
    const std::string key = "platform.joints[" + std::to_string(i) + "]";
    if (!j.isMap()) return Fail(error, key + ": expected a map");
    geometry::DhJoint joint;
    if (j["name"].isString()) joint.name = static_cast<std::string>(j["name"]);
    if (!ReadNumber(j["theta_offset"], key + ".theta_offset", &joint.theta_offset, error) ||
        !ReadNumber(j["d"], key + ".d", &joint.d, error) ||
        !ReadNumber(j["a"], key + ".a", &joint.a, error) ||
        !ReadNumber(j["alpha"], key + ".alpha", &joint.alpha, error) ||
        !ReadNumber(j["radians_per_tick"], key + ".radians_per_tick", &joint.radians_per_tick,
                    error)) {
      return false;
    }
    model->joints.push_back(joint);
  }
  std::string why;
  if (!model->Check(&why)) return Fail(error, "platform: " + why);
  return true;
}

bool ValidateCamera(const CameraCalibration& c, const std::string& key, std::string* error) {
  if (!c.P.allFinite()) return Fail(error, key + ".P: holds a non-finite value");
  const Eigen::Matrix3d M = c.P.leftCols<3>();
  const double scale = M.norm();
  if (!(scale > 0) || !(std::abs(M.determinant()) > 1e-12 * scale * scale * scale)) {
    return Fail(error, key + ".P: camera centre is not finite (left 3x3 block is singular)");
  }
  if (!geometry::ProjectiveCamera(c.P, c.image_size).Center().allFinite()) {
    return Fail(error, key + ".P: camera centre is not finite");
  }
  if (c.image_size.width <= 0 || c.image_size.height <= 0) {
    return Fail(error, key + ".image_size: width and height must be positive");
  }
  if (c.K) {
    const Eigen::Matrix3d& K = *c.K;
    if (!K.allFinite()) return Fail(error, key + ".K: holds a non-finite value");
    if (K(1, 0) != 0 || K(2, 0) != 0 || K(2, 1) != 0 || K(2, 2) == 0) {
      return Fail(error, key + ".K: must be upper triangular with K(2,2) non-zero");
    }
    if (!(std::abs(K.determinant()) > 0)) return Fail(error, key + ".K: is singular");
  }
  if (!c.dist.empty() && !c.K) return Fail(error, key + ".dist: needs " + key + ".K");
  std::string why;
  if (!geometry::CheckDistortion(c.dist, &why)) return Fail(error, key + ".dist: " + why);
  return true;
}

cv::Mat ToCv(const Eigen::MatrixXd& m) {
  cv::Mat out;
  cv::eigen2cv(m, out);
  return out;
}

void WriteCamera(cv::FileStorage& fs, const std::string& key, const CameraCalibration& c) {
  fs << key << "{";
  fs << "P" << ToCv(c.P);
  fs << "image_size"
     << "[:" << c.image_size.width << c.image_size.height << "]";
  if (c.K) fs << "K" << ToCv(*c.K);
  if (!c.dist.empty()) {
    fs << "dist"
       << ToCv(Eigen::Map<const Eigen::RowVectorXd>(c.dist.data(),
                                                    static_cast<Eigen::Index>(c.dist.size())));
  }
  fs << "}";
}

}  // namespace

geometry::ProjectiveCamera CameraCalibration::Camera() const {
  if (K) return geometry::ProjectiveCamera(P, image_size, geometry::Lens{*K, dist});
  return geometry::ProjectiveCamera(P, image_size);
}

bool ValidateCalibration(const StereoCalibration& c, std::string* error) {
  if (!ValidateCamera(c.left, "left", error) || !ValidateCamera(c.right, "right", error)) {
    return false;
  }
  if (c.ranger) {
    if (!c.ranger->origin.allFinite()) return Fail(error, "ranger.origin: not finite");
    if (!c.ranger->axis.allFinite() || !(c.ranger->axis.norm() > 0)) {
      return Fail(error, "ranger.axis: must be finite and non-zero");
    }
  }
  std::string why;
  if (c.platform && !c.platform->Check(&why)) return Fail(error, "platform: " + why);
  return true;
}

namespace {

std::optional<StereoCalibration> ParseText(const std::string& yaml, std::string* error) {
  StereoCalibration c;
  try {
    cv::FileStorage fs(
        yaml, cv::FileStorage::READ | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML);
    if (!fs.isOpened()) {
      Fail(error, "calibration: not a YAML document");
      return std::nullopt;
    }
    if (!ReadCamera(fs["left"], "left", &c.left, error) ||
        !ReadCamera(fs["right"], "right", &c.right, error)) {
      return std::nullopt;
    }
    const cv::FileNode ranger = fs["ranger"];
    if (!ranger.empty() && !ranger.isNone()) {
      RangerCalibration r;
      if (!ReadVector3(ranger["origin"], "ranger.origin", &r.origin, error) ||
          !ReadVector3(ranger["axis"], "ranger.axis", &r.axis, error)) {
        return std::nullopt;
      }
      if (!(r.axis.norm() > 0)) {
        Fail(error, "ranger.axis: must be non-zero");
        return std::nullopt;
      }
      r.axis.normalize();
      c.ranger = r;
    }
    const cv::FileNode platform = fs["platform"];
    if (!platform.empty() && !platform.isNone()) {
      geometry::PlatformModel model;
      if (!ReadPlatform(platform, &model, error)) return std::nullopt;
      c.platform = model;
    }
  } catch (const cv::Exception& e) {
    Fail(error, "calibration: YAML parse error: " + e.err);
    return std::nullopt;
  }
  if (!ValidateCalibration(c, error)) return std::nullopt;
  return c;
}

}  // namespace

Result<StereoCalibration> ParseCalibration(const std::string& yaml) {
  std::string why;
  auto c = ParseText(yaml, &why);
  if (!c) return ErrorMessage{why};
  return std::move(*c);
}

Result<StereoCalibration> LoadCalibration(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return ErrorMessage{path + ": cannot open the calibration file"};
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto c = ParseCalibration(text);
  if (!c.ok()) return ErrorMessage{path + ": " + c.error()};
  return c;
}

std::string FormatCalibration(const StereoCalibration& c) {
  std::string why;
  if (!ValidateCalibration(c, &why)) throw std::invalid_argument("invalid calibration: " + why);
  cv::FileStorage fs(".yaml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  WriteCamera(fs, "left", c.left);
  WriteCamera(fs, "right", c.right);
  if (c.ranger) {
    fs << "ranger"
       << "{";
    fs << "origin"
       << "[:" << c.ranger->origin.x() << c.ranger->origin.y() << c.ranger->origin.z() << "]";
    fs << "axis"
       << "[:" << c.ranger->axis.x() << c.ranger->axis.y() << c.ranger->axis.z() << "]";
    fs << "}";
  }
  if (c.platform) {
    fs << "platform"
       << "{";
    fs << "world_from_base" << ToCv(c.platform->world_from_base.matrix());
    fs << "joints"
       << "[";
    for (const auto& j : c.platform->joints) {
      fs << "{:"
         << "name" << j.name << "theta_offset" << j.theta_offset << "d" << j.d << "a" << j.a
         << "alpha" << j.alpha << "radians_per_tick" << j.radians_per_tick << "}";
    }
    fs << "]"
       << "}";
  }
  return fs.releaseAndGetString();
}

bool SaveCalibration(const StereoCalibration& c, const std::string& path, std::string* error) {
  const std::string text = FormatCalibration(c);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  if (!out) {
    if (error) *error = path + ": cannot write the calibration file";
    return false;
  }
  return true;
}

}  // namespace igms::calibration
