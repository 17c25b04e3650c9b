#include "common/calibration/calibration_hash.h"

#include <openssl/evp.h>

#include <cstdio>
#include <stdexcept>

namespace igms::calibration {
namespace {

// "%.17g" gives every double a text that reads back to it; -0 and 0 are one value here.
void Number(std::string* out, double v) {
  char text[32];
  std::snprintf(text, sizeof text, " %.17g", v == 0.0 ? 0.0 : v);
  *out += text;
}

void Matrix(std::string* out, const std::string& key, const Eigen::MatrixXd& m) {
  *out += key + " " + std::to_string(m.rows()) + " " + std::to_string(m.cols());
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    for (Eigen::Index c = 0; c < m.cols(); ++c) Number(out, m(r, c));
  *out += "\n";
}

void Camera(std::string* out, const std::string& key, const CameraCalibration& c) {
  Matrix(out, key + ".P", c.P);
  *out += key + ".image_size " + std::to_string(c.image_size.width) + " " +
          std::to_string(c.image_size.height) + "\n";
  if (c.K) {
    Matrix(out, key + ".K", *c.K);
  } else {
    *out += key + ".K none\n";
  }
  *out += key + ".dist " + std::to_string(c.dist.size());
  for (double d : c.dist) Number(out, d);
  *out += "\n";
}

}  // namespace

std::string CanonicalCalibrationText(const StereoCalibration& c) {
  std::string out = "igms-calibration-hash 1\n";
  Camera(&out, "left", c.left);
  Camera(&out, "right", c.right);
  if (c.ranger) {
    out += "ranger.origin";
    for (int i = 0; i < 3; ++i) Number(&out, c.ranger->origin[i]);
    out += "\nranger.axis";
    for (int i = 0; i < 3; ++i) Number(&out, c.ranger->axis[i]);
    out += "\n";
  } else {
    out += "ranger none\n";
  }
  if (c.platform) {
    Matrix(&out, "platform.world_from_base", c.platform->world_from_base.matrix());
    out += "platform.joints " + std::to_string(c.platform->joints.size()) + "\n";
    for (size_t i = 0; i < c.platform->joints.size(); ++i) {
      const geometry::DhJoint& j = c.platform->joints[i];
      // The name with its length, so no name can pass for a number or another line.
      out += "platform.joints[" + std::to_string(i) + "] " + std::to_string(j.name.size()) + ":" +
             j.name;
      for (double v : {j.theta_offset, j.d, j.a, j.alpha, j.radians_per_tick}) Number(&out, v);
      out += "\n";
    }
  } else {
    out += "platform none\n";
  }
  return out;
}

std::string Sha256Hex(std::string_view bytes) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr) != 1 ||
      length != 32) {
    throw std::runtime_error("libcrypto's SHA-256 failed");
  }
  static const char kHex[] = "0123456789abcdef";
  std::string hex;
  for (unsigned int i = 0; i < length; ++i) {
    hex += kHex[digest[i] >> 4];
    hex += kHex[digest[i] & 0xf];
  }
  return hex;
}

std::string CalibrationHash(const StereoCalibration& calibration) {
  return Sha256Hex(CanonicalCalibrationText(calibration));
}

}  // namespace igms::calibration
