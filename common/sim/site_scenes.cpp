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

namespace {

// Builds one site scene: the sensor and lighting drawn first, then the objects, each group
// placed where it is apart from the others. Every draw comes from one generator, in a fixed
// order, so a (seed, level, hd) always gives the same scene.
class SceneBuilder {
 public:
  SceneBuilder(uint64_t seed, SiteLevel level, bool hd)
      : set_(LevelSettings(level)),
        level_(level),
        rng_(seed * 7919 + static_cast<uint64_t>(level) * 104729 + (hd ? 1 : 0)),
        px_(hd ? 1920.0 / 512.0 : 1.0) {  // the level's pixel sizes are the thesis's
    s_.cameras = hd ? HdCameras() : ThesisCameras();
    s_.sensor.seed = seed;
  }

  Scene Build() {
    DrawSensorAndLighting();
    eye_ = s_.cameras.left.Center();
    const int n = static_cast<int>(uni(set_.min_objects, set_.max_objects + 1 - 1e-9));
    for (int i = 0; i < n; ++i) PlaceOne();
    return std::move(s_);
  }

 private:
  double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
  bool chance(double p) { return uni(0, 1) < p; }

  void DrawSensorAndLighting() {
    s_.sensor.noise_sigma = uni(set_.noise_min, set_.noise_max);
    s_.sensor.blur_sigma = uni(0.5, 1.2);
    s_.table.albedo = uni(set_.table_albedo_min, set_.table_albedo_max);
    s_.table.hole_albedo = 0.2 * s_.table.albedo;
    s_.lighting.ambient = uni(0.3, 0.45);
    s_.lighting.lights = {{Eigen::Vector3d(uni(-0.6, 0.6), uni(-0.4, 0.4), 1.0), uni(0.35, 0.5)},
                          {Eigen::Vector3d(uni(-0.5, 0.5), 1.0, uni(0.2, 0.6)), uni(0.15, 0.3)}};
    s_.lighting.shadows = true;
  }

  // One object (or a pipe with its supports), of the kind the level favours.
  void PlaceOne() {
    const double k = uni(0, 1);
    if (level_ == SiteLevel::kPipes) {
      // Mostly pipes, with an upright pipe or a block among them now and then.
      if (k < 0.7)
        Place(&SceneBuilder::Pipe);
      else if (k < 0.85)
        Place(&SceneBuilder::UprightPipe);
      else
        Place(&SceneBuilder::Block);
    } else {
      if (k < 0.4)
        Place(&SceneBuilder::UprightPipe);
      else if (k < 0.7)
        Place(&SceneBuilder::Pipe);
      else
        Place(&SceneBuilder::Block);
    }
  }

  void Material(SceneObject& o) {
    o.albedo = uni(set_.albedo_min, set_.albedo_max);
    if (chance(set_.textured_share)) o.texture = {uni(0.1, 0.35), uni(0.6, 2.0)};
  }

  std::string Name(const std::string& kind) { return kind + "_" + std::to_string(count_++); }

  // Places the group made at table point `at` (drawn afresh each attempt); false when it
  // found no room.
  bool Place(Group (SceneBuilder::*make)(const Eigen::Vector2d&)) {
    for (int attempt = 0; attempt < 400; ++attempt) {
      const double dist = uni(set_.min_distance, set_.max_distance);
      const double half_width = 0.24 * dist;
      const Eigen::Vector2d at(eye_.x() + uni(-half_width, half_width), eye_.y() - dist);
      Group g = (this->*make)(at);
      Rect l, r;
      std::vector<std::pair<Eigen::Vector2d, double>> feet;
      if (!Fits(g, l, r, feet)) continue;
      left_rects_.push_back(l);
      right_rects_.push_back(r);
      footprints_.insert(footprints_.end(), feet.begin(), feet.end());
      for (auto& o : g.objects) s_.objects.push_back(std::move(o));
      return true;
    }
    return false;
  }

  // Whether group g is in view, in the images and on the table apart from the groups placed
  // already; its rectangles in both images and its footprints on the table come out.
  bool Fits(const Group& g, Rect& l, Rect& r,
            std::vector<std::pair<Eigen::Vector2d, double>>& feet) const {
    bool ok = true, first = true;
    Eigen::Vector2d fc;
    double fr = 0;
    for (const auto& o : g.objects) {
      Rect lo, ro;
      if (!Bounds(o.shape, s_.cameras.left, lo) || !Bounds(o.shape, s_.cameras.right, ro)) {
        ok = false;
        break;
      }
      l = first ? lo : Union(l, lo);
      r = first ? ro : Union(r, ro);
      first = false;
      Footprint(o.shape, fc, fr);
      feet.push_back({fc, fr});
    }
    if (!ok) return false;
    const double margin = 8 * px_;
    const Rect lm{l.u0 - margin, l.v0 - margin, l.u1 + margin, l.v1 + margin};
    const Rect rm{r.u0 - margin, r.v0 - margin, r.u1 + margin, r.v1 + margin};
    if (InsideShare(lm, s_.cameras.left.image_size()) < set_.min_inside ||
        InsideShare(rm, s_.cameras.right.image_size()) < set_.min_inside)
      return false;
    if (set_.min_inside < 1.0 && (InsideShare(l, s_.cameras.left.image_size()) < set_.min_inside ||
                                  InsideShare(r, s_.cameras.right.image_size()) < set_.min_inside))
      return false;
    for (size_t i = 0; i < left_rects_.size() && ok && set_.image_gap >= 0; ++i)
      ok = Apart(l, left_rects_[i], set_.image_gap * px_) &&
           Apart(r, right_rects_[i], set_.image_gap * px_);
    // Solids never meet, whatever the image shows.
    for (const auto& [c, rad] : feet)
      for (const auto& [c2, rad2] : footprints_)
        if (ok && (c - c2).norm() < rad + rad2 + 0.3) ok = false;
    return ok;
  }

  Group UprightPipe(const Eigen::Vector2d& at) {
    Group g;
    SceneObject o(Name("upright"), Upright(at, chance(0.5) ? 0.5 : 0.25, uni(3.0, 12.0)));
    Material(o);
    g.objects.push_back(o);
    return g;
  }

  Group Block(const Eigen::Vector2d& at) {
    Group g;
    const Eigen::Vector3d size(uni(1.0, 4.0), uni(1.0, 4.0), uni(1.0, 4.0));
    SceneObject o(Name("box"), site::Block({at.x(), at.y(), 0.0}, size,
                                           chance(0.5) ? uni(-40.0, 40.0) * kDeg : 0.0));
    Material(o);
    g.objects.push_back(o);
    return g;
  }

  // A lying pipe in any horizontal direction: on the table, raised on two blocks, or tilted
  // with one end on a block.
  Group Pipe(const Eigen::Vector2d& at) {
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
    SceneObject o(Name("lying"), c);
    Material(o);
    g.objects.push_back(o);
    const double depth = 0.8 * r * 2;  // along the pipe
    auto support = [&](double along, double height) {
      const Eigen::Vector3d p = c.center + along * c.axis;
      SceneObject b(Name("support"), site::Block({p.x(), p.y(), 0.0}, {depth, bw, height}, yaw));
      Material(b);
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
  }

  const Settings set_;
  const SiteLevel level_;
  std::mt19937_64 rng_;
  const double px_;
  Scene s_;
  Eigen::Vector3d eye_;
  std::vector<Rect> left_rects_, right_rects_;
  std::vector<std::pair<Eigen::Vector2d, double>> footprints_;
  int count_ = 0;
};

}  // namespace

Scene SiteScene(uint64_t seed, SiteLevel level, bool hd) {
  return SceneBuilder(seed, level, hd).Build();
}

}  // namespace igms::site
