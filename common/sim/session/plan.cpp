#include "common/sim/session/plan.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "common/sim/capture/sim_capture.h"

namespace igms::site {
namespace {

Eigen::Vector3d CenterOf(const Shape& shape) {
  return std::visit([](const auto& s) -> Eigen::Vector3d { return s.center; }, shape);
}

StereoCameras AtPan(const Scene& scene, const std::optional<geometry::PlatformModel>& platform,
                    double pan_deg) {
  video::PoseStamp pose;
  pose.joints_rad = {pan_deg * M_PI / 180.0, 0.0, 0.0};
  pose.from_platform = true;
  return video::CamerasAtPose(scene.cameras, platform, pose);
}

// The pan (a multiple of 0.25 degrees) that brings the object's centre nearest the left
// image's centre column; 0 without a platform model (the cameras cannot turn).
double CentringPan(const Scene& scene, const std::optional<geometry::PlatformModel>& platform,
                   const Shape& shape, const PlanOptions& options) {
  if (!platform || !options.pan) return 0.0;
  const Eigen::Vector3d center = CenterOf(shape);
  double best = 0.0, best_offset = INFINITY;
  for (double pan = -options.max_pan_deg; pan <= options.max_pan_deg + 1e-9; pan += 0.25) {
    const auto uv = AtPan(scene, platform, pan).left.Project(center);
    if (!uv) continue;
    const double offset = std::abs(uv->x() - scene.cameras.left.image_size().width / 2.0);
    if (offset < best_offset) {
      best_offset = offset;
      best = pan;
    }
  }
  return best;
}

std::string Point(const Eigen::Vector3d& p) {
  return fmt::format("[{:.4f}, {:.4f}, {:.4f}]", p.x(), p.y(), p.z());
}

}  // namespace

Result<std::vector<PlannedObject>> PlanSession(
    const Scene& scene, const std::optional<geometry::PlatformModel>& platform,
    const PlanOptions& options) {
  std::vector<PlannedObject> plan;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Shape& shape = scene.objects[i].shape;
    if (std::holds_alternative<Sphere>(shape)) continue;  // IGMS models cylinders and boxes
    PlannedObject p;
    p.index = i;
    p.name = scene.objects[i].name.empty() ? fmt::format("#{}", i) : scene.objects[i].name;
    if (!options.only.empty() &&
        std::find(options.only.begin(), options.only.end(), p.name) == options.only.end()) {
      continue;
    }
    p.box = std::holds_alternative<Box>(shape);
    p.yaw_deg = CentringPan(scene, platform, shape, options);
    const auto marks = GenerateMarks(shape, AtPan(scene, platform, p.yaw_deg).left,
                                     options.mark_seed * 1000 + i, options.marks);
    if (!marks) {
      return ErrorMessage{
          fmt::format("object {} cannot be marked: it is not wholly in front of "
                      "the left camera at pan {:.2f} degrees",
                      p.name, p.yaw_deg)};
    }
    p.marks = *marks;
    plan.push_back(std::move(p));
  }
  for (const std::string& name : options.only) {
    if (std::none_of(plan.begin(), plan.end(),
                     [&](const PlannedObject& p) { return p.name == name; })) {
      return ErrorMessage{"the scene has no cylinder or box named '" + name + "'"};
    }
  }
  return plan;
}

std::string PlanScript(const std::vector<PlannedObject>& plan, const std::string& origin,
                       const PlanOptions& options) {
  std::string s = fmt::format(
      "# A modelling session planned by igms-plan for {} (mark seed {}).\n"
      "# Play it with: igms-control --config LAB --script THIS_FILE (docs/scripts.md)\n",
      origin, options.mark_seed);
  for (const PlannedObject& p : plan) {
    s += fmt::format("\n# {} ({})\n", p.name, p.box ? "box" : "cylinder");
    s += fmt::format("- look: {{yaw: {:.2f}}}\n", p.yaw_deg);
    s += "- wait_for: {mode: verification}\n";
    s += "- button: freeze\n";
    // The range first, as the operator takes it: the pointer jumps to the beam's echo.
    if (options.range) s += "- range\n";
    for (const Eigen::Vector3d& m : p.marks) {
      s += fmt::format("- move_to: {{point: {}, timeout: {:g}}}\n", Point(m),
                       options.move_timeout_s);
      s += "- trigger\n";
    }
    s += fmt::format("- say: {}\n", p.box ? "box" : "cylinder");
    if (options.screenshots) {
      std::string file = p.name;  // a file name whatever the object is called
      for (char& c : file) {
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-') c = '_';
      }
      s += fmt::format("- screenshot: overlay-{:02d}-{}.png\n", p.index, file);
    }
    s += "- button: unfreeze\n";
  }
  return s;
}

}  // namespace igms::site
