#include "common/sim/site_scenes.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "common/sim/testbed.h"

namespace igms::site {
namespace {

constexpr double kDeg = M_PI / 180.0;

struct Rect {
  double u0 = 0, v0 = 0, u1 = 0, v1 = 0;
};

// A pipe and its supports, or one object: placed together, kept apart from the others.
struct Group {
  std::vector<SceneObject> objects;
};

bool Bounds(const Shape& shape, const geometry::ProjectiveCamera& camera, Rect& r) {
  return ImageBounds(shape, camera, r.u0, r.v0, r.u1, r.v1);
}

Rect Union(const Rect& a, const Rect& b) {
  return {std::min(a.u0, b.u0), std::min(a.v0, b.v0), std::max(a.u1, b.u1), std::max(a.v1, b.v1)};
}

bool Apart(const Rect& a, const Rect& b, double gap) {
  return a.u1 + gap < b.u0 || b.u1 + gap < a.u0 || a.v1 + gap < b.v0 || b.v1 + gap < a.v0;
}

// The share of the rectangle's area inside the image.
double InsideShare(const Rect& r, const geometry::ImageSize& size) {
  const double w = std::max(1e-9, r.u1 - r.u0), h = std::max(1e-9, r.v1 - r.v0);
  const double iw = std::max(0.0, std::min(r.u1, size.width - 1.0) - std::max(r.u0, 0.0));
  const double ih = std::max(0.0, std::min(r.v1, size.height - 1.0) - std::max(r.v0, 0.0));
  return iw * ih / (w * h);
}

// The footprint on the table: centre and radius of a circle holding the solid's outline.
void Footprint(const Shape& shape, Eigen::Vector2d& c, double& r) {
  const auto points = OutlinePoints(shape, 36);
  Eigen::Vector2d lo(1e18, 1e18), hi(-1e18, -1e18);
  for (const auto& p : points) {
    lo = lo.cwiseMin(p.head<2>());
    hi = hi.cwiseMax(p.head<2>());
  }
  c = 0.5 * (lo + hi);
  r = 0.5 * (hi - lo).norm();
}

Cylinder Upright(const Eigen::Vector2d& at, double r, double h) {
  Cylinder c;
  c.center = {at.x(), at.y(), h / 2};
  c.axis = Eigen::Vector3d::UnitZ();
  c.radius = r;
  c.height = h;
  return c;
}

Box Block(const Eigen::Vector3d& base_centre, const Eigen::Vector3d& size, double yaw) {
  Box b;
  b.center = base_centre + Eigen::Vector3d(0, 0, size.z() / 2);
  b.size = size;
  b.rotation = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return b;
}

struct Settings {
  double min_distance = 36, max_distance = 84;
  int min_objects = 3, max_objects = 5;
  double image_gap = 12;    // thesis pixels between groups' rectangles; < 0: may overlap
  double min_inside = 1.0;  // share of a group's rectangle inside both images
  double albedo_min = 0.45, albedo_max = 0.9;
  double textured_share = 0.0;  // of the objects
  double table_albedo_min = 0.12, table_albedo_max = 0.12;
  double noise_min = 1, noise_max = 8;
};

Settings LevelSettings(SiteLevel level) {
  Settings s;
  switch (level) {
    case SiteLevel::kPipes:
      s.min_objects = 2;
      s.max_objects = 4;
      s.noise_max = 5;
      break;
    case SiteLevel::kClutter:
      s.max_distance = 96;
      s.min_objects = 4;
      s.max_objects = 8;
      s.image_gap = -1;
      s.min_inside = 0.6;
      s.albedo_min = 0.2;
      s.albedo_max = 0.95;
      s.textured_share = 0.5;
      s.table_albedo_min = 0.08;
      s.table_albedo_max = 0.35;
      break;
    case SiteLevel::kFar:
      s.min_distance = 72;
      s.max_distance = 96;
      s.min_objects = 4;
      s.max_objects = 6;
      s.image_gap = 8;
      s.noise_min = s.noise_max = 6;
      break;
  }
  return s;
}

}  // namespace

const char* SiteLevelName(SiteLevel level) {
  switch (level) {
    case SiteLevel::kPipes:
      return "pipes";
    case SiteLevel::kClutter:
      return "clutter";
    case SiteLevel::kFar:
      return "far";
  }
  return "unknown";
}

StereoCameras HdCameras() {
  const StereoCameras thesis = ThesisCameras();
  const double k = 1920.0 / 512.0;
  // u' = k u, v' = k v - (k * 480 - 1080) / 2: the same view across, cropped top and bottom.
  Eigen::Matrix3d S;
  S << k, 0, 0, 0, k, -(k * 480 - 1080) / 2, 0, 0, 1;
  const geometry::ImageSize size{1920, 1080};
  return {geometry::ProjectiveCamera(S * thesis.left.P(), size),
          geometry::ProjectiveCamera(S * thesis.right.P(), size)};
}

Scene SiteScene(uint64_t seed, SiteLevel level, bool hd) {
  const Settings set = LevelSettings(level);
  std::mt19937_64 rng(seed * 7919 + static_cast<uint64_t>(level) * 104729 + (hd ? 1 : 0));
  auto uni = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  auto chance = [&](double p) { return uni(0, 1) < p; };
  Scene s;
  s.cameras = hd ? HdCameras() : ThesisCameras();
  const double px = hd ? 1920.0 / 512.0 : 1.0;  // the level's pixel sizes are the thesis's
  s.sensor.seed = seed;
  s.sensor.noise_sigma = uni(set.noise_min, set.noise_max);
  s.sensor.blur_sigma = uni(0.5, 1.2);
  s.table.albedo = uni(set.table_albedo_min, set.table_albedo_max);
  s.table.hole_albedo = 0.2 * s.table.albedo;
  s.lighting.ambient = uni(0.3, 0.45);
  s.lighting.lights = {{Eigen::Vector3d(uni(-0.6, 0.6), uni(-0.4, 0.4), 1.0), uni(0.35, 0.5)},
                       {Eigen::Vector3d(uni(-0.5, 0.5), 1.0, uni(0.2, 0.6)), uni(0.15, 0.3)}};
  s.lighting.shadows = true;

  const Eigen::Vector3d eye = s.cameras.left.Center();
  std::vector<Rect> left_rects, right_rects;
  std::vector<std::pair<Eigen::Vector2d, double>> footprints;
  int count = 0;
  auto material = [&](SceneObject& o) {
    o.albedo = uni(set.albedo_min, set.albedo_max);
    if (chance(set.textured_share)) o.texture = {uni(0.1, 0.35), uni(0.6, 2.0)};
  };
  // Places the group made at table point `at` (drawn afresh each attempt); false when it
  // found no room.
  auto place = [&](auto make) {
    for (int attempt = 0; attempt < 400; ++attempt) {
      const double dist = uni(set.min_distance, set.max_distance);
      const double half_width = 0.24 * dist;
      const Eigen::Vector2d at(eye.x() + uni(-half_width, half_width), eye.y() - dist);
      Group g = make(at);
      Rect l, r;
      bool ok = true, first = true;
      Eigen::Vector2d fc;
      double fr = 0;
      std::vector<std::pair<Eigen::Vector2d, double>> feet;
      for (const auto& o : g.objects) {
        Rect lo, ro;
        if (!Bounds(o.shape, s.cameras.left, lo) || !Bounds(o.shape, s.cameras.right, ro)) {
          ok = false;
          break;
        }
        l = first ? lo : Union(l, lo);
        r = first ? ro : Union(r, ro);
        first = false;
        Footprint(o.shape, fc, fr);
        feet.push_back({fc, fr});
      }
      if (!ok) continue;
      const double margin = 8 * px;
      const Rect lm{l.u0 - margin, l.v0 - margin, l.u1 + margin, l.v1 + margin};
      const Rect rm{r.u0 - margin, r.v0 - margin, r.u1 + margin, r.v1 + margin};
      if (InsideShare(lm, s.cameras.left.image_size()) < set.min_inside ||
          InsideShare(rm, s.cameras.right.image_size()) < set.min_inside)
        continue;
      if (set.min_inside < 1.0 && (InsideShare(l, s.cameras.left.image_size()) < set.min_inside ||
                                   InsideShare(r, s.cameras.right.image_size()) < set.min_inside))
        continue;
      for (size_t i = 0; i < left_rects.size() && ok && set.image_gap >= 0; ++i)
        ok = Apart(l, left_rects[i], set.image_gap * px) &&
             Apart(r, right_rects[i], set.image_gap * px);
      // Solids never meet, whatever the image shows.
      for (const auto& [c, rad] : feet)
        for (const auto& [c2, rad2] : footprints)
          if (ok && (c - c2).norm() < rad + rad2 + 0.3) ok = false;
      if (!ok) continue;
      left_rects.push_back(l);
      right_rects.push_back(r);
      footprints.insert(footprints.end(), feet.begin(), feet.end());
      for (auto& o : g.objects) s.objects.push_back(std::move(o));
      return true;
    }
    return false;
  };
  auto name = [&](const std::string& kind) { return kind + "_" + std::to_string(count++); };
  auto upright = [&](const Eigen::Vector2d& at) {
    Group g;
    SceneObject o(name("upright"), Upright(at, chance(0.5) ? 0.5 : 0.25, uni(3.0, 12.0)));
    material(o);
    g.objects.push_back(o);
    return g;
  };
  auto block = [&](const Eigen::Vector2d& at) {
    Group g;
    const Eigen::Vector3d size(uni(1.0, 4.0), uni(1.0, 4.0), uni(1.0, 4.0));
    SceneObject o(name("box"),
                  Block({at.x(), at.y(), 0.0}, size, chance(0.5) ? uni(-40.0, 40.0) * kDeg : 0.0));
    material(o);
    g.objects.push_back(o);
    return g;
  };
  // A lying pipe in any horizontal direction: on the table, raised on two blocks, or tilted
  // with one end on a block.
  auto pipe = [&](const Eigen::Vector2d& at) {
    Group g;
    const double r = chance(0.5) ? 0.5 : 0.25, len = uni(3.0, 8.0);
    const double yaw = uni(0.0, 180.0) * kDeg;
    const Eigen::Vector3d dir(std::cos(yaw), std::sin(yaw), 0);
    const int how = static_cast<int>(uni(0, 3));  // 0 table, 1 raised, 2 tilted
    const double h = uni(0.75, 2.5);              // support height
    const double bw = uni(0.75, 1.5);             // support width across the pipe
    Cylinder c;
    c.radius = r;
    c.height = len;
    if (how == 0) {
      c.center = {at.x(), at.y(), r};
      c.axis = dir;
    } else if (how == 1) {
      c.center = {at.x(), at.y(), h + r};
      c.axis = dir;
    } else {
      const double tilt = std::asin(std::min(0.9, h / (0.8 * len)));
      c.axis = Eigen::Vector3d(std::cos(tilt) * dir.x(), std::cos(tilt) * dir.y(), std::sin(tilt));
      // The low end rests on the table; the high end on a block 0.8 of the way along.
      c.center = Eigen::Vector3d(at.x(), at.y(), r) + 0.5 * len * c.axis;
      c.center.z() = r + 0.5 * len * std::sin(tilt);
    }
    SceneObject o(name("lying"), c);
    material(o);
    g.objects.push_back(o);
    const double depth = 0.8 * r * 2;  // along the pipe
    auto support = [&](double along, double height) {
      const Eigen::Vector3d p = c.center + along * c.axis;
      SceneObject b(name("support"), Block({p.x(), p.y(), 0.0}, {depth, bw, height}, yaw));
      material(b);
      g.objects.push_back(b);
    };
    if (how == 1) {
      support(-0.35 * len, h);
      support(0.35 * len, h);
    } else if (how == 2) {
      const double along = 0.3 * len;  // from the centre towards the high end
      const Eigen::Vector3d p = c.center + along * c.axis;
      support(along, std::max(0.2, p.z() - r * std::sqrt(1 - c.axis.z() * c.axis.z())));
    }
    return g;
  };
  const int n = static_cast<int>(uni(set.min_objects, set.max_objects + 1 - 1e-9));
  for (int i = 0; i < n; ++i) {
    if (level == SiteLevel::kPipes) {
      // Mostly pipes, with an upright pipe or a block among them now and then.
      const double k = uni(0, 1);
      if (k < 0.7)
        place(pipe);
      else if (k < 0.85)
        place(upright);
      else
        place(block);
    } else {
      const double k = uni(0, 1);
      if (k < 0.4)
        place(upright);
      else if (k < 0.7)
        place(pipe);
      else
        place(block);
    }
  }
  return s;
}

}  // namespace igms::site
