#include "common/sim/vision/truth_table.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "common/base/json.h"
#include "object_server/solid_models.h"

namespace igms::site {
namespace {

Eigen::Vector3d V(const object::Vec3& v) { return {v.x(), v.y(), v.z()}; }

std::string Vec(const Eigen::Vector3d& v) {
  return fmt::format("[{:.4f}, {:.4f}, {:.4f}]", v.x(), v.y(), v.z());
}

}  // namespace

std::string TruthTable(const std::vector<TruthRow>& rows) {
  std::string t =
      fmt::format("{:<10} {:<8} {:>24} {:>24} {:>6} {:>19} {:>19} {:>6} {:>6} {:>7} {:>7}\n",
                  "object", "type", "true centre (in)", "modelled centre (in)", "d pos",
                  "true size", "modelled size", "d size", "d axis", "loc ms", "rtt ms");
  for (const TruthRow& r : rows) {
    auto size = [&](const Eigen::Vector3d& s) {
      return r.kind == "box" ? fmt::format("{:.2f} {:.2f} {:.2f}", s.x(), s.y(), s.z())
                             : fmt::format("r {:.3f} h {:.2f}", s.x(), s.y());
    };
    auto centre = [](const Eigen::Vector3d& c) {
      return fmt::format("{:.2f} {:.2f} {:.2f}", c.x(), c.y(), c.z());
    };
    if (!r.found) {
      t += fmt::format("{:<10} {:<8} {:>24} {:>24}   not found: {}\n", r.name, r.kind,
                       centre(r.true_center), "-", r.reason);
      continue;
    }
    t += fmt::format(
        "{:<10} {:<8} {:>24} {:>24} {:>6.3f} {:>19} {:>19} {:>6.3f} {:>6.2f} {:>7.0f} {:>7.0f}\n",
        r.name, r.kind, centre(r.true_center), centre(r.found_center), r.position_error,
        size(r.true_size), size(r.found_size), r.size_error, r.axis_error_deg, r.locate_ms,
        r.round_trip_ms);
  }
  return t;
}

std::string TruthJson(const std::vector<TruthRow>& rows, uint64_t frame_id,
                      const std::string& scene) {
  std::string j = fmt::format("{{\"frame_id\": {}, \"scene\": \"{}\", \"objects\": [\n", frame_id,
                              JsonEscape(scene));
  for (size_t i = 0; i < rows.size(); ++i) {
    const TruthRow& r = rows[i];
    j += fmt::format(
        "  {{\"name\": \"{}\", \"type\": \"{}\", \"found\": {}, \"reason\": \"{}\", "
        "\"true_center\": {}, \"modelled_center\": {}, \"true_size\": {}, \"modelled_size\": {}, "
        "\"position_error\": {:.5f}, \"size_error\": {:.5f}, \"axis_error_deg\": {:.4f}, "
        "\"locate_ms\": {:.2f}, \"fetch_ms\": {:.2f}, \"round_trip_ms\": {:.2f}}}{}\n",
        JsonEscape(r.name), r.kind, r.found ? "true" : "false", JsonEscape(r.reason),
        Vec(r.true_center), Vec(r.found_center), Vec(r.true_size), Vec(r.found_size),
        r.position_error, r.size_error, r.axis_error_deg, r.locate_ms, r.fetch_ms, r.round_trip_ms,
        i + 1 < rows.size() ? "," : "");
  }
  return j + "]}\n";
}

bool Truth(const Shape& shape, TruthRow* row, object::LocateRequest* request) {
  if (const auto* c = std::get_if<Cylinder>(&shape)) {
    row->kind = "cylinder";
    row->true_center = c->center;
    row->true_size = {c->radius, c->height, 0};
    request->set_type(object::OBJECT_TYPE_CYLINDER);
    return true;
  }
  if (const auto* b = std::get_if<Box>(&shape)) {
    row->kind = "box";
    row->true_center = b->center;
    row->true_size = b->size;  // along its own axes, as the oriented result is
    request->set_type(object::OBJECT_TYPE_BOX);
    return true;
  }
  return false;
}

void Compare(const Shape& shape, const object::LocateResponse& got, TruthRow* row) {
  row->found = got.found();
  row->locate_ms = got.locate_ms();
  row->fetch_ms = got.fetch_ms();
  if (!got.found()) {
    row->reason = object::FailureReason_Name(got.reason()) + ": " + got.detail();
    return;
  }
  if (const auto* c = std::get_if<Cylinder>(&shape)) {
    const auto& m = got.cylinder();
    row->found_center = V(m.center());
    row->found_size = {m.radius(), m.height(), 0};
    row->axis_error_deg =
        std::acos(std::min(1.0, std::abs(V(m.axis()).normalized().dot(c->axis)))) * 180 / M_PI;
  } else {
    const auto& m = got.box();
    row->found_center = V(m.center());
    row->found_size = V(m.size());
    row->axis_error_deg = object::BoxYawErrorDeg(m.yaw_deg(), std::get<Box>(shape).rotation);
  }
  row->position_error = (row->found_center - row->true_center).norm();
  row->size_error = (row->found_size - row->true_size).cwiseAbs().maxCoeff();
}

std::string ObjectName(const Scene& scene, size_t i) {
  return scene.objects[i].name.empty() ? fmt::format("#{}", i) : scene.objects[i].name;
}

}  // namespace igms::site
