#include "control/export/solids.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace igms::control {

namespace {

using Problem = std::optional<std::string>;

Problem Finite(const std::string& name, double v) {
  if (std::isfinite(v)) return std::nullopt;
  return name + (std::isnan(v) ? " is NaN" : " is infinite");
}

Problem FiniteVec(const std::string& name, const object::Vec3& v) {
  if (auto p = Finite(name + ".x", v.x())) return p;
  if (auto p = Finite(name + ".y", v.y())) return p;
  return Finite(name + ".z", v.z());
}

Problem Positive(const std::string& name, double v) {
  if (auto p = Finite(name, v)) return p;
  if (v <= 0) return name + " is not positive (" + std::to_string(v) + ")";
  return std::nullopt;
}

Problem NonNegative(const std::string& name, double v) {
  if (auto p = Finite(name, v)) return p;
  if (v < 0) return name + " is negative (" + std::to_string(v) + ")";
  return std::nullopt;
}

Problem Sigmas(const std::string& name, const object::Vec3& v) {
  if (auto p = NonNegative(name + ".x", v.x())) return p;
  if (auto p = NonNegative(name + ".y", v.y())) return p;
  return NonNegative(name + ".z", v.z());
}

Problem CheckGeometry(const ModelRecord& r) {
  if (r.type == object::OBJECT_TYPE_CYLINDER) {
    const auto& c = r.cylinder;
    if (auto p = FiniteVec("cylinder.center", c.center())) return p;
    if (auto p = FiniteVec("cylinder.axis", c.axis())) return p;
    const double n = std::hypot(c.axis().x(), c.axis().y(), c.axis().z());
    if (std::abs(n - 1) > 1e-3) {
      return "cylinder.axis is not a unit vector (length " + std::to_string(n) + ")";
    }
    if (auto p = Positive("cylinder.radius", c.radius())) return p;
    if (auto p = Positive("cylinder.height", c.height())) return p;
    if (auto p = Sigmas("cylinder.center_sigma", c.center_sigma())) return p;
    if (auto p = NonNegative("cylinder.radius_sigma", c.radius_sigma())) return p;
    return NonNegative("cylinder.height_sigma", c.height_sigma());
  }
  if (r.type == object::OBJECT_TYPE_BOX) {
    const auto& b = r.box;
    if (auto p = FiniteVec("box.center", b.center())) return p;
    if (auto p = Positive("box.size.x", b.size().x())) return p;
    if (auto p = Positive("box.size.y", b.size().y())) return p;
    if (auto p = Positive("box.size.z", b.size().z())) return p;
    if (auto p = Finite("box.yaw_deg", b.yaw_deg())) return p;
    if (auto p = Sigmas("box.center_sigma", b.center_sigma())) return p;
    if (auto p = Sigmas("box.size_sigma", b.size_sigma())) return p;
    return NonNegative("box.yaw_sigma_deg", b.yaw_sigma_deg());
  }
  return "type " + std::to_string(r.type) + " is neither a cylinder nor a box";
}

}  // namespace

std::optional<std::string> CheckExportModel(const StoredModel& model) {
  if (auto p = CheckGeometry(model.record)) {
    return "model " + std::to_string(model.id) + ": " + *p;
  }
  return std::nullopt;
}

std::optional<ExportFormat> ParseExportFormat(const std::string& name) {
  for (ExportFormat f : AllExportFormats()) {
    if (name == ExportFormatName(f)) return f;
  }
  return std::nullopt;
}

const char* ExportFormatName(ExportFormat format) {
  switch (format) {
    case ExportFormat::kScene:
      return "scene";
    case ExportFormat::kUrdf:
      return "urdf";
    case ExportFormat::kGltf:
      return "gltf";
    case ExportFormat::kGlb:
      return "glb";
    case ExportFormat::kObj:
      return "obj";
    case ExportFormat::kStl:
      return "stl";
    case ExportFormat::kJson:
      return "json";
  }
  return "?";
}

const char* ExportExtension(ExportFormat format) {
  switch (format) {
    case ExportFormat::kScene:
      return ".scene";
    case ExportFormat::kUrdf:
      return ".urdf";
    case ExportFormat::kGltf:
      return ".gltf";
    case ExportFormat::kGlb:
      return ".glb";
    case ExportFormat::kObj:
      return ".obj";
    case ExportFormat::kStl:
      return ".stl";
    case ExportFormat::kJson:
      return ".json";
  }
  return "";
}

std::vector<ExportFormat> AllExportFormats() {
  return {ExportFormat::kScene, ExportFormat::kUrdf, ExportFormat::kGltf, ExportFormat::kGlb,
          ExportFormat::kObj,   ExportFormat::kStl,  ExportFormat::kJson};
}

std::optional<LengthUnit> ParseLengthUnit(const std::string& name) {
  if (name == "in" || name == "inch" || name == "inches") return LengthUnit{"in", 0.0254};
  if (name == "ft" || name == "foot" || name == "feet") return LengthUnit{"ft", 0.3048};
  if (name == "m" || name == "metre" || name == "metres" || name == "meter" || name == "meters") {
    return LengthUnit{"m", 1.0};
  }
  if (name == "cm") return LengthUnit{"cm", 0.01};
  if (name == "mm") return LengthUnit{"mm", 0.001};
  return std::nullopt;
}

Result<Eigen::Isometry3d> ParseBaseTransform(const std::string& text) {
  std::vector<double> v;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    if (item.empty() || end == item.c_str() || *end != '\0' || !std::isfinite(x)) {
      return ErrorMessage{"'" + text + "' is not six finite numbers x,y,z,roll,pitch,yaw"};
    }
    v.push_back(x);
  }
  if (v.size() != 6) {
    return ErrorMessage{"'" + text + "' has " + std::to_string(v.size()) +
                        " numbers, not six (x,y,z,roll,pitch,yaw)"};
  }
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = (Eigen::AngleAxisd(v[5], Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(v[4], Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(v[3], Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  t.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  return t;
}

namespace exporting {

namespace {

Eigen::Vector3d E(const object::Vec3& v) { return {v.x(), v.y(), v.z()}; }

constexpr double kPi = 3.14159265358979323846;

}  // namespace

double ToleranceOut(const ExportOptions& options) {
  return kTessellationToleranceInches * 0.0254 / options.out_units.metres;
}

int CylinderSides(double radius, double tolerance) {
  if (tolerance >= radius) return 8;
  const double half_angle = std::acos(1 - tolerance / radius);
  const double n = std::ceil(kPi / half_angle);
  return static_cast<int>(std::clamp(n, 8.0, 16384.0));
}

Result<std::vector<Solid>> MakeSolids(const std::vector<StoredModel>& models,
                                      const ExportOptions& options) {
  if (!std::isfinite(options.padding_sigmas) || options.padding_sigmas < 0) {
    return ErrorMessage{"the padding must be a finite number of sigmas, 0 or more"};
  }
  for (const auto& m : models) {
    if (auto problem = CheckExportModel(m)) return ErrorMessage{*problem + "; nothing written"};
  }
  const double scale = options.world_units.metres / options.out_units.metres;
  const double k = options.padding_sigmas;
  const double tolerance = ToleranceOut(options);
  std::vector<Solid> solids;
  solids.reserve(models.size());
  for (const auto& m : models) {
    Solid s;
    s.model = &m;
    s.name = "model_" + std::to_string(m.id);
    Eigen::Isometry3d world_from_solid = Eigen::Isometry3d::Identity();
    if (m.record.type == object::OBJECT_TYPE_CYLINDER) {
      const auto& c = m.record.cylinder;
      s.cylinder = true;
      const Eigen::Vector3d z = E(c.axis()).normalized();
      const Eigen::Vector3d helper =
          std::abs(z.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
      const Eigen::Vector3d x = (helper - helper.dot(z) * z).normalized();
      world_from_solid.linear() << x, z.cross(x), z;
      world_from_solid.translation() = E(c.center()) * scale;
      // Each surface out by K sigmas of its position: the side by the radius's and the
      // centre's (its largest coordinate's), each end by half the height's and the centre's.
      const double center_sigma = E(c.center_sigma()).maxCoeff();
      s.radius = (c.radius() + k * std::hypot(c.radius_sigma(), center_sigma)) * scale;
      s.height = (c.height() + 2 * k * std::hypot(c.height_sigma() / 2, center_sigma)) * scale;
      s.sides = CylinderSides(s.radius, tolerance);
    } else {
      const auto& b = m.record.box;
      const double yaw = b.yaw_deg() * kPi / 180;
      world_from_solid.linear() =
          Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      world_from_solid.translation() = E(b.center()) * scale;
      // A face moves with the centre and half its size; the side faces' ends also swing
      // with the yaw, by half the other side's length times its sigma.
      const Eigen::Vector3d size = E(b.size());
      const Eigen::Vector3d sc = E(b.center_sigma());
      const Eigen::Vector3d ss = E(b.size_sigma());
      const double yaw_sigma = b.yaw_sigma_deg() * kPi / 180;
      const double horizontal = std::max(sc.x(), sc.y());
      const double face_x = std::sqrt(horizontal * horizontal + ss.x() * ss.x() / 4 +
                                      std::pow(size.y() / 2 * yaw_sigma, 2));
      const double face_y = std::sqrt(horizontal * horizontal + ss.y() * ss.y() / 4 +
                                      std::pow(size.x() / 2 * yaw_sigma, 2));
      const double face_z = std::sqrt(sc.z() * sc.z() + ss.z() * ss.z() / 4);
      s.size = (size + 2 * k * Eigen::Vector3d(face_x, face_y, face_z)) * scale;
      s.textured = !b.texture_png().empty();
    }
    s.pose = options.base_from_world * world_from_solid;
    solids.push_back(std::move(s));
  }
  return solids;
}

namespace {

void AddVertex(Mesh& mesh, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
               const Eigen::Vector2d& uv) {
  mesh.positions.push_back(p.cast<float>());
  mesh.normals.push_back(n.cast<float>());
  mesh.uvs.push_back(uv.cast<float>());
}

Mesh BoxMesh(const Eigen::Vector3d& size) {
  Mesh mesh;
  const Eigen::Vector3d h = size / 2;
  // Each face: its normal axis and sign; u and v run along the other two axes so that
  // u x v points out (counter-clockwise from outside).
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign : {1, -1}) {
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      n[axis] = sign;
      Eigen::Vector3d u = Eigen::Vector3d::Zero();
      Eigen::Vector3d v = Eigen::Vector3d::Zero();
      u[(axis + 1) % 3] = 1;
      v[(axis + 2) % 3] = 1;
      if (sign < 0) std::swap(u, v);
      const auto base = static_cast<std::uint32_t>(mesh.positions.size());
      const Eigen::Vector3d c = n.cwiseProduct(h);
      const Eigen::Vector3d du = u.cwiseProduct(h);
      const Eigen::Vector3d dv = v.cwiseProduct(h);
      // Image v runs down, so the face's +v edge is the image's top.
      AddVertex(mesh, c - du - dv, n, {0, 1});
      AddVertex(mesh, c + du - dv, n, {1, 1});
      AddVertex(mesh, c + du + dv, n, {1, 0});
      AddVertex(mesh, c - du + dv, n, {0, 0});
      for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(base + i);
    }
  }
  return mesh;
}

Mesh CylinderMesh(double radius, double height, int sides) {
  Mesh mesh;
  const double h = height / 2;
  // The side: a ring of sides + 1 columns (the seam twice, for the texture coordinate).
  for (int i = 0; i <= sides; ++i) {
    const double a = 2 * kPi * i / sides;
    const Eigen::Vector3d n(std::cos(a), std::sin(a), 0);
    const double u = static_cast<double>(i) / sides;
    AddVertex(mesh, radius * n + Eigen::Vector3d(0, 0, -h), n, {u, 1});
    AddVertex(mesh, radius * n + Eigen::Vector3d(0, 0, h), n, {u, 0});
  }
  for (int i = 0; i < sides; ++i) {
    const auto b = static_cast<std::uint32_t>(2 * i);
    for (std::uint32_t j : {0u, 2u, 3u, 0u, 3u, 1u}) mesh.indices.push_back(b + j);
  }
  // The ends: a centre and a rim each, facing out along the axis.
  for (int sign : {1, -1}) {
    const Eigen::Vector3d n(0, 0, sign);
    const auto centre = static_cast<std::uint32_t>(mesh.positions.size());
    AddVertex(mesh, Eigen::Vector3d(0, 0, sign * h), n, {0.5, 0.5});
    for (int i = 0; i < sides; ++i) {
      const double a = 2 * kPi * i / sides;
      AddVertex(mesh, Eigen::Vector3d(radius * std::cos(a), radius * std::sin(a), sign * h), n,
                {0.5 + 0.5 * std::cos(a), 0.5 - 0.5 * std::sin(a)});
    }
    for (int i = 0; i < sides; ++i) {
      const std::uint32_t a = centre + 1 + static_cast<std::uint32_t>(i);
      const std::uint32_t b = centre + 1 + static_cast<std::uint32_t>((i + 1) % sides);
      mesh.indices.push_back(centre);
      mesh.indices.push_back(sign > 0 ? a : b);
      mesh.indices.push_back(sign > 0 ? b : a);
    }
  }
  return mesh;
}

}  // namespace

Mesh MeshOf(const Solid& solid) {
  return solid.cylinder ? CylinderMesh(solid.radius, solid.height, solid.sides)
                        : BoxMesh(solid.size);
}

Eigen::Vector3d RollPitchYaw(const Eigen::Matrix3d& r) {
  // R = Rz(yaw) Ry(pitch) Rx(roll); pitch in [-pi/2, pi/2].
  const double pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  double roll, yaw;
  if (std::abs(r(2, 0)) < 1 - 1e-12) {
    roll = std::atan2(r(2, 1), r(2, 2));
    yaw = std::atan2(r(1, 0), r(0, 0));
  } else {  // gimbal lock: put it all in yaw
    roll = 0;
    yaw = std::atan2(-r(0, 1), r(1, 1));
  }
  return {roll, pitch, yaw};
}

std::string Num(double value) {
  if (value == 0) return "0";  // no "-0"
  char text[40];
  std::snprintf(text, sizeof text, "%.12g", value);
  return text;
}

}  // namespace exporting
}  // namespace igms::control
