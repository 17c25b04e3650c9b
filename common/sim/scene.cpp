#include "common/sim/scene.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace igms::site {

double AlbedoAt(const SceneObject& object, const Eigen::Vector3d& p) {
  if (!object.texture.enabled()) return object.albedo;
  // Three directions no axis-aligned face is parallel to, so every face shows a pattern.
  static const Eigen::Vector3d kDirections[3] = {Eigen::Vector3d(0.80, 0.36, 0.48).normalized(),
                                                 Eigen::Vector3d(-0.28, 0.88, 0.38).normalized(),
                                                 Eigen::Vector3d(0.42, -0.31, 0.85).normalized()};
  const double k = 2.0 * M_PI / object.texture.period;
  double n = 0.0;
  for (const auto& a : kDirections) n += std::sin(k * a.dot(p));
  return object.albedo * (1.0 + object.texture.contrast * n / 3.0);
}
namespace {

// Two unit vectors completing `w` to a right-handed orthonormal frame.
void Frame(const Eigen::Vector3d& w, Eigen::Vector3d& u, Eigen::Vector3d& v) {
  u = w.unitOrthogonal();
  v = w.cross(u);
}

}  // namespace

Eigen::Vector3d Box::AlignedMin() const { return center - 0.5 * (rotation.cwiseAbs() * size); }
Eigen::Vector3d Box::AlignedMax() const { return center + 0.5 * (rotation.cwiseAbs() * size); }

std::optional<Hit> Intersect(const Shape& shape, const Eigen::Vector3d& origin,
                             const Eigen::Vector3d& dir) {
  const SolidFromOrigin solid(shape, origin);
  double t;
  int face;
  if (!solid.Hit(dir, std::numeric_limits<double>::infinity(), &t, &face)) return std::nullopt;
  return Hit{t, solid.Normal(dir, t, face), face};
}

SolidFromOrigin::SolidFromOrigin(const Shape& shape, const Eigen::Vector3d& origin) {
  if (const auto* c = std::get_if<Cylinder>(&shape)) {
    kind_ = Kind::kCylinder;
    w_ = c->axis;
    const Eigen::Vector3d o = origin - c->center;
    ow_ = o.dot(w_);
    half_ = 0.5 * c->height;
    b_ = o - ow_ * w_;
    r2_ = c->radius * c->radius;
    c_ = b_.squaredNorm() - r2_;
  } else if (const auto* box = std::get_if<Box>(&shape)) {
    kind_ = Kind::kBox;
    rotation_ = box->rotation;
    o_ = box->rotation.transpose() * (origin - box->center);
    half_size_ = 0.5 * box->size;
  } else {
    const auto& sphere = std::get<Sphere>(shape);
    kind_ = Kind::kSphere;
    o_ = origin - sphere.center;
    r_ = sphere.radius;
    c_ = o_.squaredNorm() - r_ * r_;
  }
}

std::vector<Eigen::Vector3d> OutlinePoints(const Shape& shape, int n) {
  std::vector<Eigen::Vector3d> pts;
  if (auto* c = std::get_if<Cylinder>(&shape)) {
    Eigen::Vector3d u, v;
    Frame(c->axis, u, v);
    for (const Eigen::Vector3d& end : {c->Base(), c->Top()}) {
      for (int i = 0; i < n; ++i) {
        const double a = 2 * M_PI * i / n;
        pts.push_back(end + c->radius * (std::cos(a) * u + std::sin(a) * v));
      }
    }
  } else if (auto* b = std::get_if<Box>(&shape)) {
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d s((i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, (i & 4) ? 0.5 : -0.5);
      pts.push_back(b->center + b->rotation * s.cwiseProduct(b->size));
    }
  } else {
    const auto& s = std::get<Sphere>(shape);
    const int rings = n / 2;  // latitude steps from pole to pole, a whole number
    for (int i = 0; i <= rings; ++i) {
      const double th = M_PI * i / rings;
      for (int j = 0; j < n; ++j) {
        const double ph = 2 * M_PI * j / n;
        pts.push_back(s.center + s.radius * Eigen::Vector3d(std::sin(th) * std::cos(ph),
                                                            std::sin(th) * std::sin(ph),
                                                            std::cos(th)));
      }
    }
  }
  return pts;
}

std::string KindName(const Shape& shape) {
  if (std::holds_alternative<Cylinder>(shape)) return "cylinder";
  if (std::holds_alternative<Box>(shape)) return "box";
  return "sphere";
}

}  // namespace igms::site
