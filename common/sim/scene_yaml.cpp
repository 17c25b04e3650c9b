#include "common/sim/scene_yaml.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "common/sim/testbed.h"

namespace igms::site {
namespace {

// Parse errors inside this file are thrown as ParseError and turned into SceneLoad.error.
struct ParseError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

double Number(const YAML::Node& node, const std::string& where) {
  try {
    const double v = node.as<double>();
    if (!std::isfinite(v)) throw ParseError(where + ": not a finite number");
    return v;
  } catch (const YAML::Exception&) {
    throw ParseError(where + ": expected a number");
  }
}

double Get(const YAML::Node& map, const std::string& key, double fallback,
           const std::string& where) {
  if (!map[key]) return fallback;
  return Number(map[key], where + "." + key);
}

Eigen::VectorXd Vec(const YAML::Node& node, int n, const std::string& where) {
  if (!node.IsSequence() || static_cast<int>(node.size()) != n)
    throw ParseError(where + ": expected a list of " + std::to_string(n) + " numbers");
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = Number(node[i], where + "[" + std::to_string(i) + "]");
  return v;
}

Eigen::Vector3d Vec3(const YAML::Node& map, const std::string& key, const Eigen::Vector3d& fallback,
                     const std::string& where) {
  if (!map[key]) return fallback;
  return Vec(map[key], 3, where + "." + key);
}

double Positive(const YAML::Node& map, const std::string& key, double fallback,
                const std::string& where) {
  const double v = Get(map, key, fallback, where);
  if (v <= 0) throw ParseError(where + "." + key + ": must be positive");
  return v;
}

Shape ParseShape(const YAML::Node& o, const std::string& where) {
  if (!o["type"]) throw ParseError(where + ": missing type (cylinder, box or sphere)");
  const std::string type = o["type"].as<std::string>();
  if (type == "cylinder") {
    Cylinder c;
    c.center = Vec3(o, "center", c.center, where);
    c.axis = Vec3(o, "axis", c.axis, where);
    if (c.axis.norm() < 1e-9) throw ParseError(where + ".axis: must not be zero");
    c.axis.normalize();
    c.radius = Positive(o, "radius", c.radius, where);
    c.height = Positive(o, "height", c.height, where);
    return c;
  }
  if (type == "box") {
    Box b;
    b.center = Vec3(o, "center", b.center, where);
    b.size = Vec3(o, "size", b.size, where);
    if (b.size.minCoeff() <= 0) throw ParseError(where + ".size: must be positive");
    const Eigen::Vector3d rpy = Vec3(o, "rpy_deg", Eigen::Vector3d::Zero(), where) * M_PI / 180;
    b.rotation = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    return b;
  }
  if (type == "sphere") {
    Sphere s;
    s.center = Vec3(o, "center", s.center, where);
    s.radius = Positive(o, "radius", s.radius, where);
    return s;
  }
  throw ParseError(where + ".type: unknown type '" + type + "' (cylinder, box or sphere)");
}

Scene Parse(const YAML::Node& root) {
  if (!root.IsMap()) throw ParseError("scene: expected a YAML map at the top level");
  Scene s;
  s.cameras = ThesisCameras();
  s.lighting = DefaultLighting();
  if (const auto c = root["cameras"]) {
    geometry::ImageSize size = s.cameras.left.image_size();
    if (c["image_size"]) {
      const Eigen::VectorXd v = Vec(c["image_size"], 2, "cameras.image_size");
      size = {static_cast<int>(v[0]), static_cast<int>(v[1])};
      if (size.width <= 0 || size.height <= 0 || size.width > 16384 || size.height > 16384)
        throw ParseError("cameras.image_size: width and height must be in 1..16384");
    }
    auto camera = [&](const char* key, const geometry::ProjectiveCamera& fallback) {
      geometry::Matrix34 P = fallback.P();
      if (c[key]) {
        const Eigen::VectorXd v = Vec(c[key], 12, std::string("cameras.") + key);
        for (int i = 0; i < 12; ++i) P(i / 4, i % 4) = v[i];
        if (std::abs(P.leftCols<3>().determinant()) < 1e-12)
          throw ParseError(std::string("cameras.") + key + ": the left 3x3 block is singular");
      }
      return geometry::ProjectiveCamera(P, size);
    };
    s.cameras = {camera("left", s.cameras.left), camera("right", s.cameras.right)};
  }
  if (const auto n = root["sensor"]) {
    s.sensor.noise_sigma = Get(n, "noise_sigma", s.sensor.noise_sigma, "sensor");
    s.sensor.blur_sigma = Get(n, "blur_sigma", s.sensor.blur_sigma, "sensor");
    if (s.sensor.noise_sigma < 0 || s.sensor.blur_sigma < 0)
      throw ParseError("sensor: sigmas must not be negative");
    if (n["seed"]) s.sensor.seed = n["seed"].as<uint64_t>();
  }
  if (const auto l = root["lighting"]) {
    s.lighting.ambient = Get(l, "ambient", s.lighting.ambient, "lighting");
    if (l["shadows"]) s.lighting.shadows = l["shadows"].as<bool>();
    if (l["lights"]) {
      s.lighting.lights.clear();
      for (size_t i = 0; i < l["lights"].size(); ++i) {
        const std::string where = "lighting.lights[" + std::to_string(i) + "]";
        Light light;
        light.direction = Vec3(l["lights"][i], "direction", light.direction, where);
        if (light.direction.norm() < 1e-9) throw ParseError(where + ".direction: must not be zero");
        light.intensity = Get(l["lights"][i], "intensity", light.intensity, where);
        s.lighting.lights.push_back(light);
      }
    }
  }
  if (const auto t = root["table"]) {
    Table& tb = s.table;
    if (t["enabled"]) tb.enabled = t["enabled"].as<bool>();
    tb.x_min = Get(t, "x_min", tb.x_min, "table");
    tb.x_max = Get(t, "x_max", tb.x_max, "table");
    tb.y_min = Get(t, "y_min", tb.y_min, "table");
    tb.y_max = Get(t, "y_max", tb.y_max, "table");
    tb.albedo = Get(t, "albedo", tb.albedo, "table");
    tb.hole_albedo = Get(t, "hole_albedo", tb.hole_albedo, "table");
    tb.hole_pitch = Positive(t, "hole_pitch", tb.hole_pitch, "table");
    tb.hole_radius = Get(t, "hole_radius", tb.hole_radius, "table");
    tb.background = Get(t, "background", tb.background, "table");
    if (t["hole_origin"]) tb.hole_origin = Vec(t["hole_origin"], 2, "table.hole_origin");
  }
  if (const auto objects = root["objects"]) {
    if (!objects.IsSequence()) throw ParseError("objects: expected a list");
    for (size_t i = 0; i < objects.size(); ++i) {
      const std::string where = "objects[" + std::to_string(i) + "]";
      SceneObject o{"object_" + std::to_string(i), ParseShape(objects[i], where), 0.85};
      if (objects[i]["name"]) o.name = objects[i]["name"].as<std::string>();
      o.albedo = Get(objects[i], "albedo", o.albedo, where);
      if (const auto tex = objects[i]["texture"]) {
        const std::string w = where + ".texture";
        if (!tex.IsMap()) throw ParseError(w + ": expected a map {contrast, period}");
        o.texture.contrast = Get(tex, "contrast", 0.3, w);
        o.texture.period = Positive(tex, "period", o.texture.period, w);
        if (o.texture.contrast < 0.0 || o.texture.contrast > 1.0) {
          throw ParseError(w + ".contrast: must be in [0, 1]");
        }
      }
      s.objects.push_back(std::move(o));
    }
  }
  return s;
}

void EmitVec(YAML::Emitter& out, const Eigen::VectorXd& v) {
  out << YAML::Flow << YAML::BeginSeq;
  for (int i = 0; i < v.size(); ++i) out << v[i];
  out << YAML::EndSeq;
}

}  // namespace

SceneLoad ParseSceneYaml(const std::string& text) {
  try {
    return {Parse(YAML::Load(text)), ""};
  } catch (const ParseError& e) {
    return {std::nullopt, e.what()};
  } catch (const YAML::Exception& e) {
    return {std::nullopt, std::string("scene: ") + e.what()};
  }
}

SceneLoad LoadSceneFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) return {std::nullopt, "cannot open scene file " + path};
  std::stringstream ss;
  ss << in.rdbuf();
  SceneLoad load = ParseSceneYaml(ss.str());
  if (!load.scene) load.error = path + ": " + load.error;
  return load;
}

std::string SceneToYaml(const Scene& s) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "cameras" << YAML::Value << YAML::BeginMap;
  const auto size = s.cameras.left.image_size();
  out << YAML::Key << "image_size" << YAML::Value;
  EmitVec(out, Eigen::Vector2d(size.width, size.height));
  for (auto [key, cam] :
       {std::pair{"left", &s.cameras.left}, std::pair{"right", &s.cameras.right}}) {
    Eigen::VectorXd v(12);
    for (int i = 0; i < 12; ++i) v[i] = cam->P()(i / 4, i % 4);
    out << YAML::Key << key << YAML::Value;
    EmitVec(out, v);
  }
  out << YAML::EndMap;
  out << YAML::Key << "sensor" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
      << "noise_sigma" << YAML::Value << s.sensor.noise_sigma << YAML::Key << "blur_sigma"
      << YAML::Value << s.sensor.blur_sigma << YAML::Key << "seed" << YAML::Value << s.sensor.seed
      << YAML::EndMap;
  out << YAML::Key << "lighting" << YAML::Value << YAML::BeginMap << YAML::Key << "ambient"
      << YAML::Value << s.lighting.ambient << YAML::Key << "lights" << YAML::Value
      << YAML::BeginSeq;
  for (const auto& l : s.lighting.lights) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "direction" << YAML::Value;
    EmitVec(out, l.direction);
    out << YAML::Key << "intensity" << YAML::Value << l.intensity << YAML::EndMap;
  }
  out << YAML::EndSeq;
  if (s.lighting.shadows) out << YAML::Key << "shadows" << YAML::Value << true;
  out << YAML::EndMap;
  const Table& t = s.table;
  out << YAML::Key << "table" << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "enabled" << YAML::Value << t.enabled;
  for (auto [k, v] : {std::pair{"x_min", t.x_min},
                      {"x_max", t.x_max},
                      {"y_min", t.y_min},
                      {"y_max", t.y_max},
                      {"albedo", t.albedo},
                      {"hole_albedo", t.hole_albedo},
                      {"hole_pitch", t.hole_pitch},
                      {"hole_radius", t.hole_radius},
                      {"background", t.background}})
    out << YAML::Key << k << YAML::Value << v;
  out << YAML::Key << "hole_origin" << YAML::Value;
  EmitVec(out, t.hole_origin);
  out << YAML::EndMap;
  out << YAML::Key << "objects" << YAML::Value << YAML::BeginSeq;
  for (const auto& o : s.objects) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "name" << YAML::Value << o.name;
    out << YAML::Key << "type" << YAML::Value << KindName(o.shape);
    if (auto* c = std::get_if<Cylinder>(&o.shape)) {
      out << YAML::Key << "center" << YAML::Value;
      EmitVec(out, c->center);
      out << YAML::Key << "axis" << YAML::Value;
      EmitVec(out, c->axis);
      out << YAML::Key << "radius" << YAML::Value << c->radius << YAML::Key << "height"
          << YAML::Value << c->height;
    } else if (auto* b = std::get_if<Box>(&o.shape)) {
      out << YAML::Key << "center" << YAML::Value;
      EmitVec(out, b->center);
      out << YAML::Key << "size" << YAML::Value;
      EmitVec(out, b->size);
      // Inverse of R = Rz(yaw) Ry(pitch) Rx(roll).
      const Eigen::Matrix3d& R = b->rotation;
      const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
      const double roll = std::atan2(R(2, 1), R(2, 2)), yaw = std::atan2(R(1, 0), R(0, 0));
      out << YAML::Key << "rpy_deg" << YAML::Value;
      EmitVec(out, Eigen::Vector3d(roll, pitch, yaw) * 180 / M_PI);
    } else {
      const auto& sp = std::get<Sphere>(o.shape);
      out << YAML::Key << "center" << YAML::Value;
      EmitVec(out, sp.center);
      out << YAML::Key << "radius" << YAML::Value << sp.radius;
    }
    out << YAML::Key << "albedo" << YAML::Value << o.albedo;
    if (o.texture.enabled()) {
      out << YAML::Key << "texture" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
          << "contrast" << YAML::Value << o.texture.contrast << YAML::Key << "period" << YAML::Value
          << o.texture.period << YAML::EndMap;
    }
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace igms::site
