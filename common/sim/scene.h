// The simulated remote site: a scene of analytic solids on the optical table, seen by the
// two calibrated cameras (Cooke, "Interactive Graphical Model Building using Virtual
// Reality", sections 4.1-4.2).
//
// Units and frames follow common/geometry/camera.h: world frame z up, inches for the
// thesis's testbed; the table top is the plane z = 0. Everything here is plain data: the
// renderer (renderer.h), the range sensor model (range.h) and the operator mark generator
// (marks.h) read it; tests and the accuracy table read the ground truth straight from it.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "common/geometry/camera.h"

namespace igms::site {

// A directional light: `direction` points from the scene towards the light (any length;
// normalised on use). Shading is Lambertian; with Lighting::shadows a solid between a
// surface point and the light takes that light away (hard shadows, as from a distant lamp).
struct Light {
  Eigen::Vector3d direction{0.0, 0.0, 1.0};
  double intensity = 0.5;
};

struct Lighting {
  double ambient = 0.35;  // added to every surface, whatever its orientation
  std::vector<Light> lights;
  bool shadows = false;  // solids cast shadows on the table and on each other
};

// The optical table: a dark rectangle in the plane z = 0 drilled with a square grid of
// holes. Outside the table the ray sees `background` (a constant radiance).
struct Table {
  bool enabled = true;
  double x_min = -3.0, x_max = 45.0;  // across the cameras' view
  double y_min = -96.0, y_max = -24.0;
  double albedo = 0.12;
  double hole_albedo = 0.02;
  double hole_pitch = 1.0;  // distance between hole centres, both axes
  double hole_radius = 0.125;
  Eigen::Vector2d hole_origin{0.0, 0.0};  // one hole's centre; the grid repeats from it
  double background = 0.03;               // radiance beyond the table's edge
};

// Solids. Albedo in [0, 1]; radiance = albedo * (ambient + sum of lights' n.l terms),
// mapped to grey levels as 255 * radiance.
struct Cylinder {
  Eigen::Vector3d center{0, 0, 0};  // midpoint of the axis segment
  Eigen::Vector3d axis{0, 0, 1};    // unit vector (normalised on load)
  double radius = 0.5;
  double height = 6.0;
  Eigen::Vector3d Base() const { return center - 0.5 * height * axis; }
  Eigen::Vector3d Top() const { return center + 0.5 * height * axis; }
};

struct Box {
  Eigen::Vector3d center{0, 0, 0};
  Eigen::Vector3d size{1, 1, 1};                           // along the box's own axes
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // columns: box axes in world
  // Corners of the world-axis-aligned bounding box (the thesis's block model).
  Eigen::Vector3d AlignedMin() const;
  Eigen::Vector3d AlignedMax() const;
};

struct Sphere {
  Eigen::Vector3d center{0, 0, 0};
  double radius = 1.0;
};

using Shape = std::variant<Cylinder, Box, Sphere>;

// A textured material: the albedo varies over the solid's surface as a smooth solid texture
//   albedo(p) = albedo * (1 + contrast * n(p)),  n(p) = mean of sin(2 pi a_k . p / period)
// over three fixed, skewed unit directions a_k, so n is in [-1, 1]. A pattern of sines is
// band-limited: it gives stereo matching features inside the silhouette without aliasing,
// as long as one period spans at least 4 pixels in the image (1 in at 7 ft is about 4 px with
// the thesis's cameras).
struct Texture {
  double contrast = 0.0;  // 0: plain (white matte, as the thesis's test objects); at most 1
  double period = 1.0;    // inches
  bool enabled() const { return contrast > 0.0; }
};

struct SceneObject {
  SceneObject() = default;
  SceneObject(std::string name, Shape shape, double albedo = 0.85, Texture texture = {})
      : name(std::move(name)), shape(std::move(shape)), albedo(albedo), texture(texture) {}

  std::string name;
  Shape shape;
  double albedo = 0.85;  // white matte, as the thesis's test objects
  Texture texture;
};

// The object's albedo at surface point p (world frame): `albedo` when it has no texture.
double AlbedoAt(const SceneObject& object, const Eigen::Vector3d& p);

// Sensor model applied after rendering: Gaussian blur, then additive Gaussian noise, then
// rounding to 8 bits. Zero sigma turns a stage off. `seed` makes the noise repeatable;
// the left and right images draw from different streams of the same seed.
struct SensorModel {
  double noise_sigma = 2.0;  // grey levels
  double blur_sigma = 0.7;   // pixels
  uint64_t seed = 1;
};

struct StereoCameras {
  geometry::ProjectiveCamera left;
  geometry::ProjectiveCamera right;
};

struct Scene {
  StereoCameras cameras;
  Lighting lighting;
  Table table;
  SensorModel sensor;
  std::vector<SceneObject> objects;
};

// Ray-solid intersection, used by the renderer and the range model. `t` is the distance
// along a unit direction; `face` tells apart the surfaces of one solid (0 = cylinder side or
// sphere, 1/2 = cylinder caps, 0..5 = box faces) so shading steps can be anti-aliased.
struct Hit {
  double t = 0.0;
  Eigen::Vector3d normal{0, 0, 1};
  int face = 0;
};
std::optional<Hit> Intersect(const Shape& shape, const Eigen::Vector3d& origin,
                             const Eigen::Vector3d& dir);

// A solid seen from one ray origin, for many rays from it (a camera's every pixel): what
// depends on the origin alone is worked out once, and the normal only for the hit kept.
// Intersect() is this for one ray.
class SolidFromOrigin {
 public:
  SolidFromOrigin(const Shape& shape, const Eigen::Vector3d& origin);
  // The nearest hit along unit direction `dir` closer than `limit`: its t and face.
  bool Hit(const Eigen::Vector3d& dir, double limit, double* t, int* face) const;
  // The outward unit normal at the hit (t, face) along `dir`.
  Eigen::Vector3d Normal(const Eigen::Vector3d& dir, double t, int face) const;

 private:
  enum class Kind { kCylinder, kBox, kSphere } kind_;
  // Cylinder: axis w, the origin's part across it (b) and along it (ow) from the centre.
  // Box: its rotation and the origin in its frame (o). Sphere: the origin from the centre (o).
  Eigen::Vector3d w_, b_, o_, half_size_;
  Eigen::Matrix3d rotation_;
  double ow_ = 0, half_ = 0, r_ = 0, r2_ = 0, c_ = 0;
};

// Defined here, inline: the renderer calls these for every ray it casts.
inline constexpr double kHitEps = 1e-9;  // nearer hits are the origin's own surface

inline bool SolidFromOrigin::Hit(const Eigen::Vector3d& d, double limit, double* t_hit,
                                 int* face) const {
  double best = std::numeric_limits<double>::infinity();
  int best_face = 0;
  auto offer = [&](double t, int f) {
    if (t > kHitEps && t < best) {
      best = t;
      best_face = f;
    }
  };
  if (kind_ == Kind::kCylinder) {
    const double dw = d.dot(w_);
    const Eigen::Vector3d a = d - dw * w_;
    const double A = a.squaredNorm(), B = 2.0 * a.dot(b_);
    if (A > kHitEps) {
      const double disc = B * B - 4 * A * c_;
      if (disc >= 0) {
        const double s = std::sqrt(disc), inv = 0.5 / A;
        for (double t : {(-B - s) * inv, (-B + s) * inv}) {
          if (std::abs(ow_ + t * dw) <= half_) {
            offer(t, 0);
            break;  // the nearer root on the finite side wins; the far one only if cut off
          }
        }
      }
    }
    if (std::abs(dw) > kHitEps) {
      const double inv_dw = 1.0 / dw;
      for (int sign : {1, -1}) {
        const double t = (sign * half_ - ow_) * inv_dw;
        if ((b_ + t * a).squaredNorm() <= r2_) offer(t, sign > 0 ? 1 : 2);
      }
    }
  } else if (kind_ == Kind::kBox) {
    const Eigen::Vector3d db = rotation_.transpose() * d;
    double t_near = -std::numeric_limits<double>::infinity();
    double t_far = std::numeric_limits<double>::infinity();
    int axis_near = 0;
    double sign_near = 1;
    for (int i = 0; i < 3; ++i) {
      const double h = half_size_[i];
      if (std::abs(db[i]) < kHitEps) {
        if (std::abs(o_[i]) > h) return false;
        continue;
      }
      double t0 = (-h - o_[i]) / db[i], t1 = (h - o_[i]) / db[i];
      double s = -1;  // entering through the -h face
      if (t0 > t1) {
        std::swap(t0, t1);
        s = 1;
      }
      if (t0 > t_near) {
        t_near = t0;
        axis_near = i;
        sign_near = s;
      }
      t_far = std::min(t_far, t1);
    }
    if (t_near > t_far || t_near <= kHitEps) return false;
    offer(t_near, 2 * axis_near + (sign_near > 0 ? 1 : 0));
  } else {
    const double b = o_.dot(d), disc = b * b - c_;
    if (disc < 0) return false;
    offer(-b - std::sqrt(disc), 0);  // the origin inside or behind: nothing visible
  }
  if (!(best < limit)) return false;
  *t_hit = best;
  *face = best_face;
  return true;
}

inline Eigen::Vector3d SolidFromOrigin::Normal(const Eigen::Vector3d& d, double t, int face) const {
  switch (kind_) {
    case Kind::kCylinder: {
      if (face == 1) return w_;
      if (face == 2) return -w_;
      const Eigen::Vector3d a = d - d.dot(w_) * w_;
      return (b_ + t * a).normalized();
    }
    case Kind::kBox: {
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      n[face / 2] = face % 2 ? 1.0 : -1.0;
      return rotation_ * n;
    }
    case Kind::kSphere:
      break;
  }
  return (o_ + t * d) / r_;
}

// Points on the solid's surface whose projections' convex hull is its image silhouette
// (cap circles for a cylinder, corners for a box, a dense sampling for a sphere).
std::vector<Eigen::Vector3d> OutlinePoints(const Shape& shape, int circle_samples = 90);

// A short human-readable kind: "cylinder", "box", "sphere".
std::string KindName(const Shape& shape);

}  // namespace igms::site
