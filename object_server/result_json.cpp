#include "object_server/result_json.h"

#include <cstdio>
#include <sstream>

#include "common/base/json.h"

namespace igms::object {
namespace {

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string Vec(const Eigen::Vector3d& v) {
  return "[" + Num(v.x()) + ", " + Num(v.y()) + ", " + Num(v.z()) + "]";
}

}  // namespace

std::string ResultToJson(const LocateResult& r) {
  std::ostringstream o;
  const char* type = r.type == SolidType::kCylinder ? "cylinder" : "box";
  o << "{\"found\": " << (r.found ? "true" : "false") << ", \"type\": \"" << type << "\"";
  if (!r.found) {
    o << ", \"reason\": \"" << FailureName(r.reason) << "\", \"detail\": \"" << JsonEscape(r.detail)
      << "\"";
  } else if (r.type == SolidType::kCylinder) {
    const auto& c = r.cylinder;
    o << ", \"center\": " << Vec(c.center) << ", \"axis\": " << Vec(c.axis)
      << ", \"radius\": " << Num(c.radius) << ", \"height\": " << Num(c.height)
      << ", \"sigma\": {\"center\": " << Vec(c.center_sigma)
      << ", \"radius\": " << Num(c.radius_sigma) << ", \"height\": " << Num(c.height_sigma) << "}";
  } else {
    const auto& b = r.box;
    o << ", \"min\": " << Vec(b.min) << ", \"max\": " << Vec(b.max)
      << ", \"center\": " << Vec(b.center) << ", \"size\": " << Vec(b.size)
      << ", \"yaw_deg\": " << Num(b.yaw_deg) << ", \"texture_rect\": [" << b.texture_rect.x << ", "
      << b.texture_rect.y << ", " << b.texture_rect.x + b.texture_rect.width - 1 << ", "
      << b.texture_rect.y + b.texture_rect.height - 1
      << "], \"sigma\": {\"min\": " << Vec(b.min_sigma) << ", \"max\": " << Vec(b.max_sigma)
      << ", \"center\": " << Vec(b.center_sigma) << ", \"size\": " << Vec(b.size_sigma)
      << ", \"yaw_deg\": " << Num(b.yaw_sigma_deg) << "}";
  }
  if (r.range.used) {
    o << ", \"range\": {\"measured\": " << Num(r.range.measured)
      << ", \"constrained\": " << (r.range.constrained ? "true" : "false");
    if (r.found)
      o << ", \"expected\": [" << Num(r.range.expected_min) << ", " << Num(r.range.expected_max)
        << "], \"agrees\": " << (r.range.agrees ? "true" : "false") << ", \"detail\": \""
        << JsonEscape(r.range.detail) << "\"";
    o << "}";
  }
  o << ", \"rms_px\": [" << Num(r.rms_left_px) << ", " << Num(r.rms_right_px)
    << "], \"outline_samples\": " << r.outline_samples
    << ", \"boundary_pixels\": " << r.boundary_pixels << ", \"ssd_rms\": " << Num(r.ssd_rms)
    << ", \"elapsed_ms\": " << Num(r.elapsed_ms) << "}";
  return o.str();
}

}  // namespace igms::object
