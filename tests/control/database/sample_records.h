// Model records as the session would store them, for the database's tests, its crash-test
// writer and its benchmark.
#pragma once

#include <cstdint>
#include <string>

#include "control/database/geometric_database.h"

namespace igms::control::testing {

inline object::Vec3 V(double x, double y, double z) {
  object::Vec3 v;
  v.set_x(x);
  v.set_y(y);
  v.set_z(z);
  return v;
}

inline ModelProvenance SampleProvenance(std::uint64_t frame_id) {
  ModelProvenance p;
  p.frame_id = frame_id;
  p.left_capture_unix_ns = 1'790'000'000'000'000'000 + static_cast<std::int64_t>(frame_id);
  p.right_capture_unix_ns = p.left_capture_unix_ns + 120'000;
  p.platform_pose.add_joints_rad(0.25);
  p.platform_pose.add_joints_rad(-0.125);
  p.platform_pose.add_joints_rad(0.0);
  p.platform_pose.set_from_platform(true);
  p.platform_pose.set_time_unix_ns(p.left_capture_unix_ns - 5'000'000);
  p.marks = {V(0.1, 0.2, 1.5), V(0.3, 0.2, 1.5), V(0.3, 0.4, 1.6), V(0.1, 0.4, 1.6)};
  p.range = 1.48;
  object::RangeReport report;
  report.set_used(true);
  report.set_constrained(true);
  report.set_measured(1.48);
  report.set_expected_min(1.45);
  report.set_expected_max(1.52);
  report.set_agrees(true);
  p.range_report = report;
  p.calibration_hash = std::string(64, 'a');
  p.boundary_pixels = 812;
  p.ssd_rms = 3.25;
  p.outline_samples = 96;
  p.rms_left_px = 0.61;
  p.rms_right_px = 0.72;
  p.locate_ms = 4.5;
  p.fetch_ms = 1.25;
  p.round_trip_ms = 7.0;
  p.servers = {{"video", "igms-video-server", "0.1.0"}, {"object", "igms-object-server", "0.1.0"}};
  return p;
}

inline ModelRecord SampleCylinder(std::uint64_t frame_id = 7) {
  ModelRecord r;
  r.type = object::OBJECT_TYPE_CYLINDER;
  *r.cylinder.mutable_center() = V(0.2, 0.3, 1.55);
  *r.cylinder.mutable_axis() = V(0, 0, 1);
  r.cylinder.set_radius(0.05);
  r.cylinder.set_height(0.4);
  *r.cylinder.mutable_center_sigma() = V(0.002, 0.002, 0.004);
  r.cylinder.set_radius_sigma(0.001);
  r.cylinder.set_height_sigma(0.003);
  r.provenance = SampleProvenance(frame_id);
  return r;
}

// A PNG signature followed by `size` bytes: the database stores a texture's bytes as given.
inline std::string SamplePng(std::size_t size, unsigned seed = 1) {
  std::string png("\x89PNG\r\n\x1a\n", 8);
  for (std::size_t i = 0; i < size; ++i) {
    seed = seed * 1103515245u + 12345u;
    png.push_back(static_cast<char>(seed >> 16));
  }
  return png;
}

inline ModelRecord SampleBox(std::uint64_t frame_id = 8, std::size_t texture_bytes = 6000) {
  ModelRecord r;
  r.type = object::OBJECT_TYPE_BOX;
  auto& b = r.box;
  *b.mutable_center() = V(0.5, -0.1, 1.2);
  *b.mutable_size() = V(0.3, 0.2, 0.25);
  b.set_yaw_deg(12.5);
  *b.mutable_center_sigma() = V(0.003, 0.003, 0.005);
  *b.mutable_size_sigma() = V(0.004, 0.004, 0.006);
  b.set_yaw_sigma_deg(0.8);
  *b.mutable_min() = V(0.33, -0.22, 1.075);
  *b.mutable_max() = V(0.67, 0.02, 1.325);
  *b.mutable_min_sigma() = V(0.003, 0.003, 0.004);
  *b.mutable_max_sigma() = V(0.003, 0.003, 0.004);
  b.set_texture_u0(100);
  b.set_texture_v0(80);
  b.set_texture_u1(179);
  b.set_texture_v1(139);
  b.set_texture_png(SamplePng(texture_bytes, static_cast<unsigned>(frame_id)));
  r.provenance = SampleProvenance(frame_id);
  r.provenance.range = 0;
  r.provenance.range_report.reset();
  r.provenance.platform_pose.clear_joints_rad();
  r.provenance.platform_pose.set_from_platform(false);
  return r;
}

}  // namespace igms::control::testing
