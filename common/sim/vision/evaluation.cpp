#include "common/sim/vision/evaluation.h"

#include <spdlog/spdlog.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "common/sim/marks.h"
#include "common/sim/renderer.h"
#include "common/sim/testbed.h"
#include "common/stats/percentile.h"
#include "object_server/debug_image.h"
#include "object_server/solid_models.h"

namespace igms::object {
namespace {

// DIR/SCENE_OBJECT followed by `ending`: where a request's debug image is written.
std::string DebugPath(const std::string& dir, const std::string& scene, const std::string& object,
                      const char* ending) {
  return dir + "/" + scene + "_" + object + ending;
}

}  // namespace

LocateOptions SiteLocateOptions() {
  LocateOptions options;
  options.floor_height = 0.0;
  return options;
}

std::vector<ObjectEvaluation> EvaluateScene(const site::Scene& scene, const std::string& scene_name,
                                            uint64_t mark_seed, const LocateOptions& options,
                                            const std::string& debug_dir, bool database) {
  const site::StereoImages images = site::RenderStereo(scene);
  const std::vector<double> seen_left = site::VisibleFractions(scene, scene.cameras.left);
  const std::vector<double> seen_right = site::VisibleFractions(scene, scene.cameras.right);
  std::vector<ObjectEvaluation> out;
  std::vector<KnownShape> known;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const auto& object = scene.objects[i];
    const auto* cyl = std::get_if<site::Cylinder>(&object.shape);
    const auto* box = std::get_if<site::Box>(&object.shape);
    if (!cyl && !box) continue;
    const auto marks = site::GenerateMarks(object.shape, scene.cameras.left, mark_seed * 1000 + i);
    if (!marks) continue;
    ObjectEvaluation e;
    e.scene_name = scene_name;
    e.object_name = object.name;
    e.visible = std::min(seen_left[i], seen_right[i]);
    LocateInput in;
    in.type = cyl ? SolidType::kCylinder : SolidType::kBox;
    in.marks = *marks;
    in.left = images.left;
    in.right = images.right;
    in.left_camera = scene.cameras.left;
    in.right_camera = scene.cameras.right;
    in.want_trace = !debug_dir.empty();
    if (database) in.known = known;
    spdlog::debug("evaluate: {} {}, asked as a {}", scene_name, object.name,
                  cyl ? "cylinder" : "box");
    e.result = Locate(in, options);
    if (e.result.found) known.push_back(KnownFromResult(e.result, object.name));
    if (!debug_dir.empty())
      cv::imwrite(DebugPath(debug_dir, scene_name, object.name, ".png"), DebugImage(in, e.result));
    const Eigen::Vector3d eye = scene.cameras.left.Center();
    if (cyl) {
      e.lying = std::abs(cyl->axis.z()) < 0.7;
      e.kind = e.lying ? "lying" : "upright";
      e.distance = (cyl->center - eye).norm();
      // The image rows' direction in space: neither the row nor the depth changes along it.
      const Eigen::Matrix3d M = scene.cameras.left.P().leftCols<3>();
      const Eigen::Vector3d v_row = M.row(1).transpose(), depth_row = M.row(2).transpose();
      const Eigen::Vector3d rows = v_row.cross(depth_row).normalized();
      e.axis_from_rows_deg =
          std::acos(std::min(1.0, std::abs(rows.dot(cyl->axis.normalized())))) * 180 / M_PI;
      if (e.result.found) {
        const auto& c = e.result.cylinder;
        e.radius_signed = c.radius - cyl->radius;
        e.height_signed = c.height - cyl->height;
        e.radius_error = std::abs(e.radius_signed);
        e.height_error = std::abs(e.height_signed);
        e.position_error = (c.center - cyl->center).norm();
        e.axis_error_deg = std::acos(std::min(1.0, std::abs(c.axis.dot(cyl->axis)))) * 180 / M_PI;
        e.z_scores = {e.radius_error / c.radius_sigma, e.height_error / c.height_sigma};
        for (int k = 0; k < 3; ++k)
          e.z_scores.push_back(std::abs(c.center[k] - cyl->center[k]) / c.center_sigma[k]);
      }
    } else {
      e.kind = "box";
      e.distance = (box->center - eye).norm();
      if (e.result.found) {
        const auto& b = e.result.box;
        // The found yaw is within 45 degrees of the true one, or of a quarter turn from it,
        // which swaps the box's x and y sizes.
        e.axis_error_deg = BoxYawErrorDeg(b.yaw_deg, box->rotation);
        const bool quarter_turn =
            std::abs(std::remainder(b.yaw_deg - StandingBoxYawDeg(box->rotation), 180.0)) > 45.0;
        Eigen::Vector3d true_size = box->size;
        if (quarter_turn) std::swap(true_size.x(), true_size.y());
        e.size_signed = b.size - true_size;
        e.size_error = e.size_signed.cwiseAbs();
        e.position_error = (b.center - box->center).norm();
        for (int k = 0; k < 3; ++k) {
          e.z_scores.push_back(e.size_error[k] / b.size_sigma[k]);
          e.z_scores.push_back(std::abs(b.center[k] - box->center[k]) / b.center_sigma[k]);
        }
      }
    }
    e.wrong = e.result.found && WrongModel(e);
    out.push_back(e);
  }
  return out;
}

std::vector<NothingThereEvaluation> EvaluateNothingThere(const site::Scene& scene,
                                                         const std::string& scene_name,
                                                         uint64_t seed, int count,
                                                         const LocateOptions& options,
                                                         const std::string& debug_dir) {
  const site::StereoImages images = site::RenderStereo(scene);
  const std::vector<double> seen_left = site::VisibleFractions(scene, scene.cameras.left);
  const std::vector<double> seen_right = site::VisibleFractions(scene, scene.cameras.right);
  std::vector<NothingThereEvaluation> out;
  auto input = [&](SolidType type, const site::Marks& marks) {
    LocateInput in;
    in.type = type;
    in.marks = marks;
    in.left = images.left;
    in.right = images.right;
    in.left_camera = scene.cameras.left;
    in.right_camera = scene.cameras.right;
    return in;
  };
  auto locate = [&](SolidType type, const site::Marks& marks) {
    spdlog::debug("evaluate: {}, marks around nothing, asked as a {}", scene_name,
                  type == SolidType::kCylinder ? "cylinder" : "box");
    return Locate(input(type, marks), options);
  };
  struct Rect {
    double u0, v0, u1, v1;
  };
  std::vector<Rect> rects;
  for (const auto& o : scene.objects) {
    Rect r;
    if (site::ImageBounds(o.shape, scene.cameras.left, r.u0, r.v0, r.u1, r.v1)) rects.push_back(r);
  }
  std::mt19937_64 rng(seed * 31 + 7);
  auto uni = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  const Eigen::Vector3d eye = scene.cameras.left.Center();
  const auto size = scene.cameras.left.image_size();
  for (int made = 0, attempt = 0; made < count && attempt < 500; ++attempt) {
    const double dist = uni(36, 96);
    site::Box phantom;
    phantom.size = {uni(1, 4), uni(1, 4), uni(1, 4)};
    phantom.center = {eye.x() + uni(-0.22, 0.22) * dist, eye.y() - dist, phantom.size.z() / 2};
    Rect r;
    if (!site::ImageBounds(phantom, scene.cameras.left, r.u0, r.v0, r.u1, r.v1)) continue;
    if (r.u0 < 20 || r.v0 < 20 || r.u1 > size.width - 20 || r.v1 > size.height - 20) continue;
    double nearest = 1e18;
    for (const auto& o : rects) {
      const double dx = std::max({0.0, o.u0 - r.u1, r.u0 - o.u1});
      const double dy = std::max({0.0, o.v0 - r.v1, r.v0 - o.v1});
      nearest = std::min(nearest, std::hypot(dx, dy));
    }
    // The marks lie up to 1 in outside the silhouette: keep them clear of every object.
    if (nearest < 16) continue;
    const auto marks = site::GenerateMarks(phantom, scene.cameras.left, seed * 1000 + 500 + made);
    if (!marks) continue;
    ++made;
    const SolidType type = made % 2 ? SolidType::kCylinder : SolidType::kBox;
    out.push_back({scene_name, nearest < 30 ? "gap" : "bare", "", locate(type, *marks)});
  }
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const auto& object = scene.objects[i];
    const bool cylinder = std::holds_alternative<site::Cylinder>(object.shape);
    if (!cylinder && !std::holds_alternative<site::Box>(object.shape)) continue;
    if (std::min(seen_left[i], seen_right[i]) < kFullView) continue;
    const auto marks = site::GenerateMarks(object.shape, scene.cameras.left, seed * 1000 + i);
    if (!marks) continue;
    LocateInput in = input(cylinder ? SolidType::kBox : SolidType::kCylinder, *marks);
    in.want_trace = !debug_dir.empty();
    spdlog::debug("evaluate: {} {}, asked as the other type, a {}", scene_name, object.name,
                  cylinder ? "box" : "cylinder");
    out.push_back({scene_name, "wrong_type", object.name, Locate(in, options)});
    if (!debug_dir.empty())
      cv::imwrite(DebugPath(debug_dir, scene_name, object.name,
                            cylinder ? "_as_box.png" : "_as_cylinder.png"),
                  DebugImage(in, out.back().result));
  }
  return out;
}

bool OffBeyondSigma(double error, double sigma) { return error > 0.5 && error > 3 * sigma; }

bool WrongModel(const ObjectEvaluation& e) {
  if (!e.result.found) return false;
  if (e.position_error > 1.0) return true;
  if (e.kind == "box") {
    for (int k = 0; k < 3; ++k)
      if (OffBeyondSigma(e.size_error[k], e.result.box.size_sigma[k])) return true;
    return false;
  }
  if (e.radius_error > 0.15) return true;
  if (e.kind == "lying") return OffBeyondSigma(e.height_error, e.result.cylinder.height_sigma);
  return e.height_error > 0.5;
}

Summary Summarize(const std::vector<ObjectEvaluation>& all, const std::string& which) {
  Summary s;
  std::vector<double> radius, height, position, time, sx, sy, sz, axis;
  int z_count = 0, z_within = 0;
  for (const auto& e : all) {
    if (!which.empty() && e.kind != which) continue;
    ++s.count;
    time.push_back(e.result.elapsed_ms);
    if (e.visible >= kFullView) {
      ++s.full;
      s.full_found += e.result.found;
      s.full_wrong += e.wrong;
    } else {
      ++s.hidden;
      s.hidden_refused += !e.result.found;
      s.hidden_wrong += e.wrong;
    }
    if (!e.result.found) continue;
    ++s.found;
    position.push_back(e.position_error);
    axis.push_back(e.axis_error_deg);
    for (const double z : e.z_scores) {
      ++z_count;
      z_within += z < 2.0;  // a NaN (no deviation reported) counts as outside
    }
    if (e.kind == "box") {
      sx.push_back(e.size_error.x());
      sy.push_back(e.size_error.y());
      sz.push_back(e.size_error.z());
    } else {
      radius.push_back(e.radius_error);
      height.push_back(e.height_error);
    }
  }
  s.found_rate = s.count ? double(s.found) / s.count : 0;
  s.full_found_rate = s.full ? double(s.full_found) / s.full : 0;
  s.radius_median = stats::Percentile(radius, 0.5);
  s.radius_p90 = stats::Percentile(radius, 0.9);
  s.height_median = stats::Percentile(height, 0.5);
  s.height_p90 = stats::Percentile(height, 0.9);
  s.position_median = stats::Percentile(position, 0.5);
  s.position_p90 = stats::Percentile(position, 0.9);
  s.size_median = {stats::Median(sx), stats::Median(sy), stats::Median(sz)};
  s.size_p90 = {stats::Percentile(sx, 0.9), stats::Percentile(sy, 0.9), stats::Percentile(sz, 0.9)};
  s.within_2_sigma = z_count ? double(z_within) / z_count : 0;
  s.axis_median_deg = stats::Percentile(axis, 0.5);
  s.axis_p90_deg = stats::Percentile(axis, 0.9);
  s.time_median_ms = stats::Percentile(time, 0.5);
  return s;
}

}  // namespace igms::object
