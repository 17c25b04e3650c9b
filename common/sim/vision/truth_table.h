// The true-versus-modelled table: each modelled object beside the simulated site's truth,
// with the errors. igms-vision-demo (the servers' own test) and igms-truth-table (a modelling
// session's database against its scene) print the same table.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/sim/scene.h"
#include "igms/object.pb.h"

namespace igms::site {

struct TruthRow {
  std::string name, kind;
  bool found = false;
  std::string reason;
  Eigen::Vector3d true_center = Eigen::Vector3d::Zero(), found_center = Eigen::Vector3d::Zero();
  // cylinder: radius, height, 0; box: its sizes along its own axes
  Eigen::Vector3d true_size = Eigen::Vector3d::Zero(), found_size = Eigen::Vector3d::Zero();
  double position_error = 0, size_error = 0, axis_error_deg = 0;
  double locate_ms = 0, fetch_ms = 0, round_trip_ms = 0;
};

// Fills the truth of one object and the request's type; false for a solid IGMS does not
// model (a sphere).
bool Truth(const Shape& shape, TruthRow* row, object::LocateRequest* request);
// The modelled solid (a LocateResponse, found or not) against the truth in `row`.
void Compare(const Shape& shape, const object::LocateResponse& got, TruthRow* row);

// The table as text, and as JSON ({"frame_id", "scene", "objects": [...]}).
std::string TruthTable(const std::vector<TruthRow>& rows);
std::string TruthJson(const std::vector<TruthRow>& rows, uint64_t frame_id,
                      const std::string& scene);

// The name of object i of a scene ("#i" when it has none).
std::string ObjectName(const Scene& scene, size_t i);

}  // namespace igms::site
