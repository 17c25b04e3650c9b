#include "control/render/draw_list.h"

#include <array>
#include <cmath>
#include <utility>

namespace igms::control::render {
namespace {

void Triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
              const Eigen::Vector3d& normal, Mesh* mesh) {
  for (const Eigen::Vector3d* p : {&a, &b, &c}) {
    mesh->triangles.push_back(p->cast<float>());
    mesh->normals.push_back(normal.cast<float>());
  }
}

void Line(const Eigen::Vector3d& a, const Eigen::Vector3d& b, Mesh* mesh) {
  mesh->lines.push_back(a.cast<float>());
  mesh->lines.push_back(b.cast<float>());
}

Eigen::Vector3d BoxCorner(const DrawModel& m, int i) {
  const Eigen::Vector3d h = 0.5 * m.size;
  const Eigen::Vector3d local((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(),
                              (i & 4) ? h.z() : -h.z());
  return m.center + m.rotation * local;
}

// The corners of the face normal to `axis` on its `sign` side (0: -, 1: +), counter-clockwise
// seen from outside, so the renderer can cull back faces (a mirroring rotation too).
std::array<Eigen::Vector3d, 4> FaceCorners(const DrawModel& m, int axis, int sign) {
  const int bit = 1 << axis, a1 = 1 << ((axis + 1) % 3), a2 = 1 << ((axis + 2) % 3);
  const int base = sign ? bit : 0;
  std::array<Eigen::Vector3d, 4> c = {BoxCorner(m, base), BoxCorner(m, base | a1),
                                      BoxCorner(m, base | a1 | a2), BoxCorner(m, base | a2)};
  // In that order they turn about the + side's normal (a1 x a2 = axis) in the box's frame.
  if ((sign == 0) != (m.rotation.determinant() < 0)) std::swap(c[1], c[3]);
  return c;
}

void AppendBox(const DrawModel& m, Mesh* mesh) {
  auto corner = [&](int i) { return BoxCorner(m, i); };
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign = 0; sign < 2; ++sign) {
      const auto c = FaceCorners(m, axis, sign);
      Eigen::Vector3d n = m.rotation.col(axis) * (sign ? 1.0 : -1.0);
      Triangle(c[0], c[1], c[2], n, mesh);
      Triangle(c[0], c[2], c[3], n, mesh);
    }
  }
  for (int i = 0; i < 8; ++i) {
    for (int bit : {1, 2, 4}) {
      if (!(i & bit)) Line(corner(i), corner(i | bit), mesh);
    }
  }
}

void AppendCylinder(const DrawModel& m, const Eigen::Vector3d& eye, int segments, Mesh* mesh) {
  const Eigen::Vector3d w = m.axis.normalized();
  const Eigen::Vector3d u = w.unitOrthogonal(), v = w.cross(u);
  const Eigen::Vector3d top = m.center + 0.5 * m.height * w, base = m.center - 0.5 * m.height * w;
  // The polygon circumscribes the circle at its edges' midpoints and inscribes it at its
  // corners: the radius of the corners is chosen so the area matches the circle's.
  const double step = 2.0 * M_PI / segments;
  const double r = m.radius * std::sqrt(step / std::sin(step));
  auto rim = [&](int i) {
    const double a = step * i;
    return Eigen::Vector3d(r * (std::cos(a) * u + std::sin(a) * v));
  };
  for (int i = 0; i < segments; ++i) {
    const Eigen::Vector3d d0 = rim(i), d1 = rim(i + 1);
    const Eigen::Vector3d side = (d0 + d1).normalized();
    Triangle(base + d0, base + d1, top + d1, side, mesh);
    Triangle(base + d0, top + d1, top + d0, side, mesh);
    Triangle(top, top + d0, top + d1, w, mesh);
    Triangle(base, base + d1, base + d0, -w, mesh);
    Line(top + d0, top + d1, mesh);
    Line(base + d0, base + d1, mesh);
  }
  // The silhouette generators: the lines of the side whose tangent plane holds the eye.
  const Eigen::Vector3d to_eye = eye - m.center;
  const Eigen::Vector3d across = to_eye - to_eye.dot(w) * w;
  const double distance = across.norm();
  if (distance > m.radius) {
    const Eigen::Vector3d n = across / distance, t = w.cross(n);
    const double c = m.radius / distance, s = std::sqrt(1.0 - c * c);
    for (double sign : {1.0, -1.0}) {
      const Eigen::Vector3d d = m.radius * (c * n + sign * s * t);
      Line(base + d, top + d, mesh);
    }
  }
}

}  // namespace

bool TexturedFace(const DrawModel& m, std::vector<Eigen::Vector3f>* triangles) {
  if (m.kind != DrawModel::Kind::kBox || m.texture.empty() || m.texture_P.isZero()) return false;
  const Eigen::Vector3d eye =
      geometry::ProjectiveCamera(m.texture_P, {1, 1}).Center();  // the size plays no part
  if (!eye.allFinite()) return false;
  double best = -1;
  int best_axis = 0, best_sign = 0;
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign = 0; sign < 2; ++sign) {
      const Eigen::Vector3d n = m.rotation.col(axis) * (sign ? 1.0 : -1.0);
      const Eigen::Vector3d face = m.center + 0.5 * m.size[axis] * n;
      const double facing = n.dot((eye - face).normalized());
      if (facing > best) {
        best = facing;
        best_axis = axis;
        best_sign = sign;
      }
    }
  }
  if (best <= 0) return false;
  // The face's own triangles, vertex for vertex, so the patch has the face's depths.
  const auto c = FaceCorners(m, best_axis, best_sign);
  for (const int i : {0, 1, 2, 0, 2, 3}) triangles->push_back(c[i].cast<float>());
  return true;
}

void AppendModel(const DrawModel& model, const Eigen::Vector3d& eye_center, int segments,
                 Mesh* mesh) {
  if (model.kind == DrawModel::Kind::kBox) {
    AppendBox(model, mesh);
  } else {
    AppendCylinder(model, eye_center, segments, mesh);
  }
}

}  // namespace igms::control::render
