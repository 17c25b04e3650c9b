// Models for the export tests and benchmark: the database tests' samples in inches-sized
// numbers, with a real PNG texture (so real consumers can decode it), and readers of the
// files the exports write.
#pragma once

#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>

#include <Eigen/Geometry>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "control/database/geometric_database.h"
#include "tests/control/database/sample_records.h"

namespace igms::control::testing {

// A real PNG: a gradient of w x h pixels.
inline std::string RealPng(int w = 32, int h = 24) {
  cv::Mat image(h, w, CV_8UC3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) image.at<cv::Vec3b>(y, x) = cv::Vec3b(x * 7, y * 9, 128);
  }
  std::vector<unsigned char> bytes;
  cv::imencode(".png", image, bytes);
  return std::string(bytes.begin(), bytes.end());
}

// A pipe of 2 in radius standing 10 in tall, tilted; a 6 x 4 x 3 in block turned by 20 deg.
inline StoredModel ExportCylinder(std::int64_t id = 3) {
  StoredModel m;
  m.id = id;
  m.record = SampleCylinder(static_cast<std::uint64_t>(id));
  auto& c = m.record.cylinder;
  *c.mutable_center() = V(10, -4, 5);
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, 0.2, 1).normalized();
  *c.mutable_axis() = V(axis.x(), axis.y(), axis.z());
  c.set_radius(2);
  c.set_height(10);
  *c.mutable_center_sigma() = V(0.02, 0.03, 0.05);
  c.set_radius_sigma(0.04);
  c.set_height_sigma(0.1);
  return m;
}

inline StoredModel ExportBox(std::int64_t id = 5) {
  StoredModel m;
  m.id = id;
  m.record = SampleBox(static_cast<std::uint64_t>(id));
  auto& b = m.record.box;
  *b.mutable_center() = V(-6, 8, 1.5);
  *b.mutable_size() = V(6, 4, 3);
  b.set_yaw_deg(20);
  *b.mutable_center_sigma() = V(0.02, 0.02, 0.03);
  *b.mutable_size_sigma() = V(0.05, 0.04, 0.06);
  b.set_yaw_sigma_deg(0.5);
  b.set_texture_png(RealPng());
  return m;
}

// JSON text as a protobuf Struct (the tests' JSON reader).
inline google::protobuf::Struct ParseJson(const std::string& text) {
  google::protobuf::Struct s;
  const auto status = google::protobuf::util::JsonStringToMessage(text, &s);
  if (!status.ok()) throw std::runtime_error("bad JSON: " + std::string(status.message()));
  return s;
}

// A binary STL's triangles: (normal, v0, v1, v2) each.
struct StlTriangle {
  Eigen::Vector3f n, v[3];
};
inline std::vector<StlTriangle> ReadStl(const std::string& bytes) {
  std::vector<StlTriangle> out;
  if (bytes.size() < 84) return out;
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  if (bytes.size() != 84 + std::size_t{count} * 50) return out;
  for (std::uint32_t i = 0; i < count; ++i) {
    float f[12];
    std::memcpy(f, bytes.data() + 84 + std::size_t{i} * 50, sizeof f);
    StlTriangle t;
    t.n = {f[0], f[1], f[2]};
    for (int k = 0; k < 3; ++k) t.v[k] = {f[3 + 3 * k], f[4 + 3 * k], f[5 + 3 * k]};
    out.push_back(t);
  }
  return out;
}

}  // namespace igms::control::testing
