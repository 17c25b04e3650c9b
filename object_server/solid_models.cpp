#include "object_server/solid_models.h"

#include <Eigen/Geometry>
#include <array>
#include <cmath>

namespace igms::object {
namespace {

// A cylinder's axis (unit, p0 to p1) and two unit vectors across it.
// The axis w and two directions u, v across it. Within 60 degrees of the vertical, u is the
// world's x, or y for an axis pointing down, carried onto the plane across w by the shortest
// rotation from the vertical, which turns smoothly with w. Eigen's unitOrthogonal, kept
// further from the vertical, turns u with the direction the axis leans, which swings fast on a
// pipe standing nearly straight up: the fit's numeric derivatives saw the rim's 64 points turn
// round the axis, and an upright pipe's radius came out with a sigma of up to 100 in.
void CylinderFrame(const Eigen::VectorXd& x, Eigen::Vector3d& w, Eigen::Vector3d& u,
                   Eigen::Vector3d& v) {
  w = x.segment<3>(3) - x.segment<3>(0);
  if (w.norm() < 1e-9) w = Eigen::Vector3d::UnitZ();
  w.normalize();
  if (std::abs(w.z()) <= 0.5) {
    u = w.unitOrthogonal();
  } else {
    const bool down = w.z() < 0;
    const Eigen::Vector3d from(0, 0, down ? -1.0 : 1.0);
    const Eigen::Vector3d across(down ? 0.0 : 1.0, down ? 1.0 : 0.0, 0);
    // Rodrigues: R = I + [k]x + [k]x^2 / (1 + c), k = from x w, c = from . w (over 0.5 here).
    const Eigen::Vector3d k = from.cross(w);
    const double c = from.dot(w);
    u = across + k.cross(across) + k.cross(k.cross(across)) / (1 + c);
    u = (u - u.dot(w) * w).normalized();
  }
  v = w.cross(u);
}

}  // namespace

// Point i of the outline: around the end at p0 for i < kCapPoints, then around p1.
std::vector<Eigen::Vector3d> CylinderOutline(const Eigen::VectorXd& x) {
  const Eigen::Vector3d p0 = x.segment<3>(0), p1 = x.segment<3>(3);
  const double r = std::abs(x[6]);
  Eigen::Vector3d w, u, v;
  CylinderFrame(x, w, u, v);
  // The fit evaluates the outline once per parameter for every Jacobian: the angles'
  // cosines and sines are worked out once.
  static const std::array<Eigen::Vector2d, kCapPoints> circle = [] {
    std::array<Eigen::Vector2d, kCapPoints> c;
    for (int i = 0; i < kCapPoints; ++i)
      c[i] = {std::cos(2 * M_PI * i / kCapPoints), std::sin(2 * M_PI * i / kCapPoints)};
    return c;
  }();
  const Eigen::Vector3d ru = r * u, rv = r * v;
  std::vector<Eigen::Vector3d> pts;
  pts.reserve(2 * static_cast<std::size_t>(kCapPoints));
  for (const Eigen::Vector3d& c : {p0, p1})
    for (const Eigen::Vector2d& cs : circle) pts.push_back(c + cs.x() * ru + cs.y() * rv);
  return pts;
}

// The rim of an end cap a camera at `centre` sees, where the pipe's side is seen too: the
// edge between the cap's face and the side (a pipe lying towards the cameras shows it as
// the inner half of an ellipse, whose width fixes the axis's turn and so the pipe's length).
std::vector<InnerEdge> CylinderInnerEdges(const Eigen::VectorXd& x, const Eigen::Vector3d& centre) {
  Eigen::Vector3d w, u, v;
  CylinderFrame(x, w, u, v);
  const double r = std::abs(x[6]);
  std::vector<InnerEdge> edges;
  for (int end = 0; end < 2; ++end) {
    const Eigen::Vector3d c = x.segment<3>(3 * Eigen::Index{end});
    const Eigen::Vector3d out = end == 0 ? -w : w;
    if (out.dot(centre - c) <= 0) continue;  // the cap faces away
    std::array<bool, kCapPoints> side_seen;
    for (int i = 0; i < kCapPoints; ++i) {
      const double a = 2 * M_PI * i / kCapPoints;
      const Eigen::Vector3d radial = std::cos(a) * u + std::sin(a) * v;
      side_seen[i] = radial.dot(centre - (c + r * radial)) > 0;
    }
    // The seen arc: from the first seen point after an unseen one, around while seen.
    int start = -1;
    for (int i = 0; i < kCapPoints; ++i)
      if (side_seen[i] && !side_seen[(i + kCapPoints - 1) % kCapPoints]) start = i;
    if (start < 0) continue;
    InnerEdge e;
    for (int k = 0; k < kCapPoints && side_seen[(start + k) % kCapPoints]; ++k)
      e.chain.push_back(end * kCapPoints + (start + k) % kCapPoints);
    const int middle = e.chain[e.chain.size() / 2] - end * kCapPoints;
    e.c1 = end * kCapPoints + (middle + kCapPoints / 2) % kCapPoints;  // across the cap
    e.c2 = (1 - end) * kCapPoints + middle;                            // along the side
    // A curved rim has no parallel neighbour beside it as a box's face edge has: a thinner
    // cap is safe to measure, and a far pipe's caps are thin.
    e.min_width_px = 2.5;
    edges.push_back(std::move(e));
  }
  return edges;
}

// A box's parameters: centre (3), size along its own axes (3) and its yaw about the world's
// vertical (a block stands on the table; the thesis's block is the yaw-0 case, 3.8.2).
Eigen::Matrix3d BoxRotation(double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// Corner i has bit k set when its coordinate k along the box's own axes is +size/2.
std::vector<Eigen::Vector3d> BoxOutline(const Eigen::VectorXd& x) {
  const Eigen::Matrix3d R = BoxRotation(x[6]);
  const Eigen::Vector3d c = x.head<3>(), h = 0.5 * x.segment<3>(3);
  std::vector<Eigen::Vector3d> pts;
  pts.reserve(8);
  for (int i = 0; i < 8; ++i)
    pts.push_back(c + R * Eigen::Vector3d((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(),
                                          (i & 4) ? h.z() : -h.z()));
  return pts;
}

// The box's edges between two faces a camera at `centre` sees. A face is seen when the
// centre lies on its outer side.
std::vector<InnerEdge> BoxInnerEdges(const Eigen::VectorXd& x, const Eigen::Vector3d& centre) {
  const Eigen::Vector3d local = BoxRotation(x[6]).transpose() * (centre - x.head<3>());
  const Eigen::Vector3d h = 0.5 * x.segment<3>(3);
  auto seen = [&](int k, int bit) {
    const double face = bit ? h[k] : -h[k];  // where the face lies; outward is away from 0
    return (face >= 0 ? 1.0 : -1.0) * (local[k] - face) > 0;
  };
  std::vector<InnerEdge> edges;
  for (int k1 = 0; k1 < 3; ++k1)
    for (int k2 = k1 + 1; k2 < 3; ++k2)
      for (int b1 = 0; b1 < 2; ++b1)
        for (int b2 = 0; b2 < 2; ++b2) {
          if (!seen(k1, b1) || !seen(k2, b2)) continue;
          const int m = 3 - k1 - k2;
          const int base = (b1 << k1) | (b2 << k2);
          edges.push_back({{base, base | (1 << m)},
                           (b1 << k1) | ((1 - b2) << k2),
                           ((1 - b1) << k1) | (b2 << k2)});
        }
  return edges;
}

// The same box with its yaw in (-45, 45] degrees and positive sizes: a quarter turn swaps
// the box's x and y sizes and leaves the solid as it was.
Eigen::VectorXd CanonicalBox(Eigen::VectorXd x) {
  x.segment<3>(3) = x.segment<3>(3).cwiseAbs();
  x[6] = std::remainder(x[6], M_PI);  // (-90, 90]
  while (x[6] > M_PI / 4) {
    x[6] -= M_PI / 2;
    std::swap(x[3], x[4]);
  }
  while (x[6] <= -M_PI / 4) {
    x[6] += M_PI / 2;
    std::swap(x[3], x[4]);
  }
  return x;
}

double StandingBoxYawDeg(const Eigen::Matrix3d& rotation) {
  return std::atan2(rotation(1, 0), rotation(0, 0)) * 180 / M_PI;
}

double BoxYawErrorDeg(double found_yaw_deg, const Eigen::Matrix3d& true_rotation) {
  return std::abs(std::remainder(found_yaw_deg - StandingBoxYawDeg(true_rotation), 90.0));
}

bool InsideSolid(bool cylinder, const Eigen::VectorXd& x, const Eigen::Vector3d& p) {
  if (cylinder) {
    const Eigen::Vector3d p0 = x.segment<3>(0), d = x.segment<3>(3) - p0;
    const double len2 = d.squaredNorm();
    if (len2 < 1e-18) return false;
    const double t = (p - p0).dot(d) / len2;
    return t >= 0 && t <= 1 && (p - p0 - t * d).norm() <= std::abs(x[6]);
  }
  const Eigen::Vector3d local = BoxRotation(x[6]).transpose() * (p - x.head<3>());
  return (local.cwiseAbs() - 0.5 * x.segment<3>(3).cwiseAbs()).maxCoeff() <= 0;
}

double ShareInside(bool a_cylinder, const Eigen::VectorXd& a, bool b_cylinder,
                   const Eigen::VectorXd& b) {
  constexpr int kSteps = 8;  // per axis: 512 points through a box, about 400 through a pipe
  int through = 0, inside = 0;
  const auto at = [](int i) { return (i + 0.5) / kSteps - 0.5; };  // in (-0.5, 0.5)
  Eigen::Vector3d w, u, v;
  if (a_cylinder) CylinderFrame(a, w, u, v);
  for (int i = 0; i < kSteps; ++i)
    for (int j = 0; j < kSteps; ++j)
      for (int k = 0; k < kSteps; ++k) {
        Eigen::Vector3d p;
        if (a_cylinder) {
          const double r = std::abs(a[6]);
          if (std::hypot(at(i), at(j)) > 0.5) continue;  // outside the disc
          p = 0.5 * (a.segment<3>(0) + a.segment<3>(3)) + 2 * r * (at(i) * u + at(j) * v) +
              at(k) * (a.segment<3>(3) - a.segment<3>(0));
        } else {
          p = a.head<3>() + BoxRotation(a[6]) *
                                a.segment<3>(3).cwiseProduct(Eigen::Vector3d(at(i), at(j), at(k)));
        }
        ++through;
        inside += InsideSolid(b_cylinder, b, p);
      }
  return through ? double(inside) / through : 0.0;
}

}  // namespace igms::object
