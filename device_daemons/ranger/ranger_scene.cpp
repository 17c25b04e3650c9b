#include "device_daemons/ranger/ranger_scene.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace igms::devices {

RangerScene RangerScene::Testbed() {
  RangerScene s;
  s.planes.push_back({{0, 0, -30}, {0, 0, 1}});
  s.planes.push_back({{120, 0, 0}, {-1, 0, 0}});
  s.cylinders.push_back({{48, 0, -30}, 3, 12});
  s.boxes.push_back({{57, 20, -30}, {63, 28, -22}});
  return s;
}

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

double HitPlane(const RangerScene::Plane& p, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  const double denom = p.normal.dot(d);
  if (std::abs(denom) < 1e-12) return kInf;
  const double t = p.normal.dot(p.point - o) / denom;
  return t > 0 ? t : kInf;
}

double HitCylinder(const RangerScene::Cylinder& c, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double best = kInf;
  // Side: |(o + t d - base).xy| = r.
  const Eigen::Vector2d p = (o - c.base).head<2>(), v = d.head<2>();
  const double a = v.squaredNorm(), b = 2 * p.dot(v), k = p.squaredNorm() - c.radius * c.radius;
  const double disc = b * b - 4 * a * k;
  if (a > 1e-12 && disc >= 0) {
    for (double t : {(-b - std::sqrt(disc)) / (2 * a), (-b + std::sqrt(disc)) / (2 * a)}) {
      const double z = o.z() + t * d.z() - c.base.z();
      if (t > 0 && z >= 0 && z <= c.height) best = std::min(best, t);
    }
  }
  // Top cap.
  if (std::abs(d.z()) > 1e-12) {
    const double t = (c.base.z() + c.height - o.z()) / d.z();
    if (t > 0 && ((o + t * d - c.base).head<2>()).norm() <= c.radius) best = std::min(best, t);
  }
  return best;
}

double HitBox(const RangerScene::Box& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double t0 = 0, t1 = kInf;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-12) {
      if (o[i] < b.min[i] || o[i] > b.max[i]) return kInf;
      continue;
    }
    double a = (b.min[i] - o[i]) / d[i], c = (b.max[i] - o[i]) / d[i];
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
    if (t0 > t1) return kInf;
  }
  return t0 > 0 ? t0 : kInf;
}
}  // namespace

std::optional<double> CastRay(const RangerScene& scene, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double best = kInf;
  for (const auto& p : scene.planes) best = std::min(best, HitPlane(p, o, d));
  for (const auto& c : scene.cylinders) best = std::min(best, HitCylinder(c, o, d));
  for (const auto& b : scene.boxes) best = std::min(best, HitBox(b, o, d));
  if (!std::isfinite(best)) return std::nullopt;
  return best;
}

std::optional<double> BeamRange(const RangerScene& scene, const RangerPose& pose, double beam_width_deg) {
  const double deg = M_PI / 180.0;
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(pose.yaw_deg * deg, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(-pose.pitch_deg * deg, Eigen::Vector3d::UnitY()))
                                .toRotationMatrix();
  std::optional<double> best = CastRay(scene, pose.origin_in, r * Eigen::Vector3d::UnitX());
  const double half = beam_width_deg / 2 * deg;
  for (int ring = 1; ring <= 3; ++ring) {
    const double off = half * ring / 3;
    for (int k = 0; k < 12; ++k) {
      const double phi = 2 * M_PI * k / 12;
      const Eigen::Vector3d local(std::cos(off), std::sin(off) * std::cos(phi), std::sin(off) * std::sin(phi));
      // Distance along the axis to the surface hit by this ray, as the echo's time says.
      if (auto t = CastRay(scene, pose.origin_in, r * local); t && (!best || *t < *best)) best = t;
    }
  }
  return best;
}

}  // namespace igms::devices
