// A model record from the session's messages, and the checks a record passes before it is
// written.
#include <cmath>
#include <set>
#include <string_view>

#include "control/database/geometric_database.h"

namespace igms::control {

namespace {

using object::Vec3;

// Each check returns the first problem it finds, named by the field's path.
using Problem = std::optional<std::string>;

Problem Finite(const std::string& name, double value) {
  if (std::isnan(value)) return name + " is NaN";
  if (std::isinf(value)) return name + " is infinite";
  return std::nullopt;
}

Problem NonNegative(const std::string& name, double value) {
  if (auto p = Finite(name, value)) return p;
  if (value < 0) return name + " is negative (" + std::to_string(value) + ")";
  return std::nullopt;
}

Problem Positive(const std::string& name, double value) {
  if (auto p = Finite(name, value)) return p;
  if (value <= 0) return name + " must be positive (found " + std::to_string(value) + ")";
  return std::nullopt;
}

Problem FiniteVec(const std::string& name, const Vec3& v) {
  if (auto p = Finite(name + ".x", v.x())) return p;
  if (auto p = Finite(name + ".y", v.y())) return p;
  return Finite(name + ".z", v.z());
}

Problem SigmaVec(const std::string& name, const Vec3& v) {
  if (auto p = NonNegative(name + ".x", v.x())) return p;
  if (auto p = NonNegative(name + ".y", v.y())) return p;
  return NonNegative(name + ".z", v.z());
}

Problem Required(const std::string& name, bool present) {
  if (!present) return name + " is missing";
  return std::nullopt;
}

Problem CheckCylinder(const object::CylinderModel& c) {
  if (auto p = Required("cylinder.center", c.has_center())) return p;
  if (auto p = Required("cylinder.axis", c.has_axis())) return p;
  if (auto p = Required("cylinder.center_sigma", c.has_center_sigma())) return p;
  if (auto p = FiniteVec("cylinder.center", c.center())) return p;
  if (auto p = FiniteVec("cylinder.axis", c.axis())) return p;
  const double length = std::sqrt(c.axis().x() * c.axis().x() + c.axis().y() * c.axis().y() +
                                  c.axis().z() * c.axis().z());
  // The locator normalises the axis; a loose tolerance only catches a missing or raw one.
  if (std::abs(length - 1) > 1e-3) {
    return "cylinder.axis is not a unit vector (length " + std::to_string(length) + ")";
  }
  if (auto p = Positive("cylinder.radius", c.radius())) return p;
  if (auto p = Positive("cylinder.height", c.height())) return p;
  if (auto p = SigmaVec("cylinder.center_sigma", c.center_sigma())) return p;
  if (auto p = NonNegative("cylinder.radius_sigma", c.radius_sigma())) return p;
  return NonNegative("cylinder.height_sigma", c.height_sigma());
}

Problem CheckBox(const object::BoxModel& b) {
  if (auto p = Required("box.center", b.has_center())) return p;
  if (auto p = Required("box.size", b.has_size())) return p;
  if (auto p = Required("box.center_sigma", b.has_center_sigma())) return p;
  if (auto p = Required("box.size_sigma", b.has_size_sigma())) return p;
  if (auto p = FiniteVec("box.center", b.center())) return p;
  if (auto p = Positive("box.size.x", b.size().x())) return p;
  if (auto p = Positive("box.size.y", b.size().y())) return p;
  if (auto p = Positive("box.size.z", b.size().z())) return p;
  if (auto p = Finite("box.yaw_deg", b.yaw_deg())) return p;
  if (auto p = SigmaVec("box.center_sigma", b.center_sigma())) return p;
  if (auto p = SigmaVec("box.size_sigma", b.size_sigma())) return p;
  if (auto p = NonNegative("box.yaw_sigma_deg", b.yaw_sigma_deg())) return p;
  // The world-axis-aligned extent is optional; when given it is whole and ordered.
  if (b.has_min() != b.has_max()) return std::string("box.min and box.max come together");
  if (b.has_min()) {
    if (auto p = FiniteVec("box.min", b.min())) return p;
    if (auto p = FiniteVec("box.max", b.max())) return p;
    if (b.min().x() > b.max().x() || b.min().y() > b.max().y() || b.min().z() > b.max().z()) {
      return std::string("box.min exceeds box.max");
    }
  }
  if (b.has_min_sigma()) {
    if (auto p = SigmaVec("box.min_sigma", b.min_sigma())) return p;
  }
  if (b.has_max_sigma()) {
    if (auto p = SigmaVec("box.max_sigma", b.max_sigma())) return p;
  }
  // The texture's rectangle matters only with a texture (the server sends u1 = u0 - 1 without).
  if (!b.texture_png().empty() &&
      (b.texture_u0() < 0 || b.texture_v0() < 0 || b.texture_u1() < b.texture_u0() ||
       b.texture_v1() < b.texture_v0())) {
    return "box.texture rectangle (" + std::to_string(b.texture_u0()) + ", " +
           std::to_string(b.texture_v0()) + ")-(" + std::to_string(b.texture_u1()) + ", " +
           std::to_string(b.texture_v1()) + ") is not a rectangle of the image";
  }
  static constexpr std::string_view kPngSignature("\x89PNG\r\n\x1a\n", 8);
  if (!b.texture_png().empty() && b.texture_png().compare(0, 8, kPngSignature) != 0) {
    return std::string("box.texture_png is not a PNG file");
  }
  return std::nullopt;
}

Problem CheckProvenance(const ModelProvenance& p) {
  if (p.frame_id == 0) return std::string("provenance.frame_id is missing (0)");
  if (p.left_capture_unix_ns <= 0) return std::string("provenance.left_capture_unix_ns is missing");
  if (p.right_capture_unix_ns <= 0) {
    return std::string("provenance.right_capture_unix_ns is missing");
  }
  const auto& joints = p.platform_pose.joints_rad();
  if (!joints.empty() && joints.size() != 3) {
    return "provenance.platform_pose.joints_rad has " + std::to_string(joints.size()) +
           " angles, not 3 (pan, tilt, roll) or none";
  }
  for (int i = 0; i < joints.size(); ++i) {
    if (auto q =
            Finite("provenance.platform_pose.joints_rad[" + std::to_string(i) + "]", joints[i])) {
      return q;
    }
  }
  if (p.marks.size() != 4) {
    return "provenance.marks has " + std::to_string(p.marks.size()) + " marks, not 4";
  }
  for (std::size_t i = 0; i < p.marks.size(); ++i) {
    if (auto q = FiniteVec("provenance.marks[" + std::to_string(i) + "]", p.marks[i])) return q;
  }
  if (auto q = NonNegative("provenance.range", p.range)) return q;
  if (p.range_report) {
    const auto& r = *p.range_report;
    if (auto q = Finite("provenance.range_report.measured", r.measured())) return q;
    if (auto q = Finite("provenance.range_report.expected_min", r.expected_min())) return q;
    if (auto q = Finite("provenance.range_report.expected_max", r.expected_max())) return q;
  }
  if (p.calibration_hash.empty()) return std::string("provenance.calibration_hash is missing");
  if (p.boundary_pixels < 0) return std::string("provenance.boundary_pixels is negative");
  if (p.outline_samples < 0) return std::string("provenance.outline_samples is negative");
  if (auto q = NonNegative("provenance.ssd_rms", p.ssd_rms)) return q;
  if (auto q = NonNegative("provenance.rms_left_px", p.rms_left_px)) return q;
  if (auto q = NonNegative("provenance.rms_right_px", p.rms_right_px)) return q;
  if (auto q = NonNegative("provenance.locate_ms", p.locate_ms)) return q;
  if (auto q = NonNegative("provenance.fetch_ms", p.fetch_ms)) return q;
  if (auto q = NonNegative("provenance.round_trip_ms", p.round_trip_ms)) return q;
  std::set<std::string> names;
  for (const auto& server : p.servers) {
    if (server.name.empty()) return std::string("provenance.servers has a server without a name");
    if (server.program.empty()) {
      return "provenance.servers: " + server.name + " has no program";
    }
    if (!names.insert(server.name).second) {
      return "provenance.servers names " + server.name + " twice";
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> CheckModelRecord(const ModelRecord& record) {
  switch (record.type) {
    case object::OBJECT_TYPE_CYLINDER:
      if (auto p = CheckCylinder(record.cylinder)) return p;
      break;
    case object::OBJECT_TYPE_BOX:
      if (auto p = CheckBox(record.box)) return p;
      break;
    default:
      return "type is " + std::to_string(record.type) + ": a model is a cylinder or a box";
  }
  return CheckProvenance(record.provenance);
}

ModelRecord MakeModelRecord(const video::GrabResponse& grab, const object::LocateRequest& request,
                            const object::LocateResponse& found, std::string calibration_hash,
                            std::vector<ServerVersion> servers, double round_trip_ms) {
  ModelRecord record;
  record.type = found.type();
  if (found.type() == object::OBJECT_TYPE_CYLINDER) record.cylinder = found.cylinder();
  if (found.type() == object::OBJECT_TYPE_BOX) record.box = found.box();
  ModelProvenance& p = record.provenance;
  p.frame_id = grab.frame_id();
  p.left_capture_unix_ns = grab.left_capture_unix_ns();
  p.right_capture_unix_ns = grab.right_capture_unix_ns();
  p.platform_pose = grab.pose();
  p.marks.assign(request.marks().begin(), request.marks().end());
  p.range = request.range();
  if (found.has_range()) p.range_report = found.range();
  p.calibration_hash = std::move(calibration_hash);
  p.boundary_pixels = found.boundary_pixels();
  p.ssd_rms = found.ssd_rms();
  p.outline_samples = found.outline_samples();
  p.rms_left_px = found.rms_left_px();
  p.rms_right_px = found.rms_right_px();
  p.locate_ms = found.locate_ms();
  p.fetch_ms = found.fetch_ms();
  p.round_trip_ms = round_trip_ms;
  p.servers = std::move(servers);
  return record;
}

}  // namespace igms::control
