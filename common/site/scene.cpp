#include "common/site/scene.h"

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

constexpr double kEps = 1e-9;

std::optional<Hit> IntersectCylinder(const Cylinder& c, const Eigen::Vector3d& origin,
                                     const Eigen::Vector3d& dir) {
  const Eigen::Vector3d& w = c.axis;
  const Eigen::Vector3d o = origin - c.center;
  const double ow = o.dot(w), dw = dir.dot(w);
  const double half = 0.5 * c.height;
  std::optional<Hit> best;
  auto offer = [&](double t, const Eigen::Vector3d& n, int face) {
    if (t > kEps && (!best || t < best->t)) best = Hit{t, n, face};
  };
  const Eigen::Vector3d a = dir - dw * w, b = o - ow * w;
  const double A = a.squaredNorm(), B = 2.0 * a.dot(b), C = b.squaredNorm() - c.radius * c.radius;
  if (A > kEps) {
    const double disc = B * B - 4 * A * C;
    if (disc >= 0) {
      const double s = std::sqrt(disc);
      for (double t : {(-B - s) / (2 * A), (-B + s) / (2 * A)}) {
        if (std::abs(ow + t * dw) <= half) {
          offer(t, (b + t * a).normalized(), 0);
          break;  // the nearer root on the finite side wins; the far one only if it is cut off
        }
      }
    }
  }
  if (std::abs(dw) > kEps) {
    for (int sign : {1, -1}) {
      const double t = (sign * half - ow) / dw;
      if ((b + t * a).squaredNorm() <= c.radius * c.radius) offer(t, sign * w, sign > 0 ? 1 : 2);
    }
  }
  return best;
}

std::optional<Hit> IntersectBox(const Box& box, const Eigen::Vector3d& origin,
                                const Eigen::Vector3d& dir) {
  const Eigen::Vector3d o = box.rotation.transpose() * (origin - box.center);
  const Eigen::Vector3d d = box.rotation.transpose() * dir;
  double t_near = -std::numeric_limits<double>::infinity();
  double t_far = std::numeric_limits<double>::infinity();
  int axis_near = 0;
  double sign_near = 1;
  for (int i = 0; i < 3; ++i) {
    const double h = 0.5 * box.size[i];
    if (std::abs(d[i]) < kEps) {
      if (std::abs(o[i]) > h) return std::nullopt;
      continue;
    }
    double t0 = (-h - o[i]) / d[i], t1 = (h - o[i]) / d[i];
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
  if (t_near > t_far || t_near <= kEps) return std::nullopt;
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  n[axis_near] = sign_near;
  return Hit{t_near, box.rotation * n, 2 * axis_near + (sign_near > 0 ? 1 : 0)};
}

std::optional<Hit> IntersectSphere(const Sphere& s, const Eigen::Vector3d& origin,
                                   const Eigen::Vector3d& dir) {
  const Eigen::Vector3d o = origin - s.center;
  const double b = o.dot(dir), c = o.squaredNorm() - s.radius * s.radius;
  const double disc = b * b - c;
  if (disc < 0) return std::nullopt;
  double t = -b - std::sqrt(disc);
  if (t <= kEps) return std::nullopt;  // camera inside or behind: nothing visible
  return Hit{t, (o + t * dir) / s.radius, 0};
}

// Two unit vectors completing `w` to a right-handed orthonormal frame.
void Frame(const Eigen::Vector3d& w, Eigen::Vector3d& u, Eigen::Vector3d& v) {
  u = w.unitOrthogonal();
  v = w.cross(u);
}

}  // namespace

Eigen::Vector3d Box::AlignedMin() const {
  return center - 0.5 * (rotation.cwiseAbs() * size);
}
Eigen::Vector3d Box::AlignedMax() const {
  return center + 0.5 * (rotation.cwiseAbs() * size);
}

std::optional<Hit> Intersect(const Shape& shape, const Eigen::Vector3d& origin,
                             const Eigen::Vector3d& dir) {
  if (auto* c = std::get_if<Cylinder>(&shape)) return IntersectCylinder(*c, origin, dir);
  if (auto* b = std::get_if<Box>(&shape)) return IntersectBox(*b, origin, dir);
  return IntersectSphere(std::get<Sphere>(shape), origin, dir);
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
    for (int i = 0; i <= n / 2; ++i) {
      const double th = M_PI * i / (n / 2);
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
