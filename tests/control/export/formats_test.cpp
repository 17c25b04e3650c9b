// The export library's formats, read back: each file parsed as its format's readers parse
// it, and its geometry checked against the models (poses, dimensions, units, padding, the
// base transform, the tessellation's tolerance), in memory, with no program run.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <regex>
#include <sstream>

#include "control/export/export.h"
#include "tests/control/export/export_samples.h"
#include "tests/support/files.h"

namespace igms::control {
namespace {

using testing::ExportBox;
using testing::ExportCylinder;
using testing::ParseJson;
using Struct = google::protobuf::Struct;

constexpr double kInch = 0.0254;
constexpr double kTolerance = 0.001 * kInch;  // the tessellation's, in metres

// The models in the output frame, in metres: what every format must describe.
struct Expected {
  bool cylinder;
  Eigen::Vector3d center;
  Eigen::Vector3d axis;  // cylinder; box: its own x axis
  double radius = 0, height = 0;
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // box

  // Signed distance from the true surface, metres (negative inside).
  double Distance(const Eigen::Vector3d& p) const {
    if (cylinder) {
      const Eigen::Vector3d d = p - center;
      const double along = d.dot(axis);
      const double radial = (d - along * axis).norm();
      const Eigen::Vector2d q(radial - radius, std::abs(along) - height / 2);
      return std::min(q.maxCoeff(), 0.0) + q.cwiseMax(0.0).norm();
    }
    const Eigen::Vector3d local = rotation.transpose() * (p - center);
    const Eigen::Vector3d q = local.cwiseAbs() - size / 2;
    return std::min(q.maxCoeff(), 0.0) + q.cwiseMax(0.0).norm();
  }
};

Expected ExpectedOf(const StoredModel& m, double padding = 0,
                    const Eigen::Isometry3d& base = Eigen::Isometry3d::Identity()) {
  Expected e;
  const auto& r = m.record;
  e.cylinder = r.type == object::OBJECT_TYPE_CYLINDER;
  if (e.cylinder) {
    const auto& c = r.cylinder;
    e.center = base * (Eigen::Vector3d(c.center().x(), c.center().y(), c.center().z()) * kInch);
    e.axis = base.linear() * Eigen::Vector3d(c.axis().x(), c.axis().y(), c.axis().z());
    const double sc = std::max({c.center_sigma().x(), c.center_sigma().y(), c.center_sigma().z()});
    e.radius = (c.radius() + padding * std::hypot(c.radius_sigma(), sc)) * kInch;
    e.height = (c.height() + 2 * padding * std::hypot(c.height_sigma() / 2, sc)) * kInch;
  } else {
    const auto& b = r.box;
    e.center = base * (Eigen::Vector3d(b.center().x(), b.center().y(), b.center().z()) * kInch);
    e.rotation = base.linear() *
                 Eigen::AngleAxisd(b.yaw_deg() * M_PI / 180, Eigen::Vector3d::UnitZ()).matrix();
    e.axis = e.rotation.col(0);
    e.size = Eigen::Vector3d(b.size().x(), b.size().y(), b.size().z()) * kInch;
    EXPECT_EQ(padding, 0) << "box padding is checked on its own";
  }
  return e;
}

const std::vector<StoredModel>& Models() {
  static const std::vector<StoredModel> models = {ExportCylinder(3), ExportBox(5)};
  return models;
}

std::vector<ExportFile> Render(ExportFormat format, const std::string& name,
                               const ExportOptions& options = {}) {
  auto files = RenderExport(Models(), format, options, name);
  EXPECT_TRUE(files.ok()) << files.error();
  return files.ok() ? *files : std::vector<ExportFile>{};
}

Eigen::Matrix3d FromQuaternion(double x, double y, double z, double w) {
  return Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix();
}

Eigen::Matrix3d FromRpy(double r, double p, double y) {
  return (Eigen::AngleAxisd(y, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// A pose read from a file against the expected one: the origin at the centre, the solid's
// z (cylinder) or x (box) along the expected axis.
void ExpectPose(const Expected& e, const Eigen::Vector3d& t, const Eigen::Matrix3d& r,
                const std::string& what) {
  EXPECT_LT((t - e.center).norm(), 1e-9) << what;
  const Eigen::Vector3d axis = e.cylinder ? r.col(2) : r.col(0);
  EXPECT_LT((axis - e.axis).norm(), 1e-9) << what;
  if (!e.cylinder) {
    EXPECT_LT((r - e.rotation).norm(), 1e-9) << what;
  }
}

// Every vertex on the true surface, and the surface between them within the tolerance:
// edge midpoints of the triangles no further than 0.001 in from it.
void ExpectOnSurface(const Expected& e, const std::vector<Eigen::Vector3d>& vertices,
                     const std::vector<std::array<int, 3>>& triangles, const std::string& what) {
  ASSERT_FALSE(triangles.empty()) << what;
  double worst_vertex = 0, worst_between = 0;
  for (const auto& t : triangles) {
    for (int k : t) worst_vertex = std::max(worst_vertex, std::abs(e.Distance(vertices[k])));
  }
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d mid = (vertices[t[k]] + vertices[t[(k + 1) % 3]]) / 2;
      worst_between = std::max(worst_between, std::abs(e.Distance(mid)));
    }
  }
  EXPECT_LT(worst_vertex, 1e-6) << what;  // float32 coordinates of ~0.3 m
  EXPECT_LT(worst_between, kTolerance) << what;
  // Not finer than it needs: a cylinder's chords use most of the tolerance.
  if (e.cylinder) {
    EXPECT_GT(worst_between, 0.5 * kTolerance) << what;
  }
}

// ---- MoveIt's .scene, read as PlanningScene::loadGeometryFromStream reads it ---------------

struct SceneObject {
  std::string id;
  Eigen::Vector3d t;
  Eigen::Matrix3d r;
  std::string shape;
  std::vector<double> dims;
  Eigen::Vector3d shape_t;
  Eigen::Vector4d shape_q, color;
  int subframes = -1;
};

bool ReadPose(std::istream& in, Eigen::Vector3d* t, Eigen::Vector4d* q) {
  return static_cast<bool>(in >> t->x() >> t->y() >> t->z() >> q->x() >> q->y() >> q->z() >>
                           q->w());
}

std::vector<SceneObject> ReadScene(const std::string& text, std::string* name) {
  std::istringstream in(text);
  std::getline(in, *name);
  std::vector<SceneObject> objects;
  while (true) {
    std::string marker;
    if (!(in >> marker)) {
      ADD_FAILURE() << "the scene ends without '.'";
      break;
    }
    if (marker == ".") break;
    EXPECT_EQ(marker, "*");
    if (marker != "*") break;
    SceneObject o;
    std::getline(in, o.id);
    o.id.erase(0, o.id.find_first_not_of(' '));
    Eigen::Vector4d q;
    EXPECT_TRUE(ReadPose(in, &o.t, &q));
    o.r = FromQuaternion(q.x(), q.y(), q.z(), q.w());
    int shapes = 0;
    in >> shapes;
    EXPECT_EQ(shapes, 1);
    in >> o.shape;
    o.dims.resize(o.shape == "box" ? 3 : 2);
    for (double& d : o.dims) in >> d;
    EXPECT_TRUE(ReadPose(in, &o.shape_t, &o.shape_q));
    EXPECT_TRUE(in >> o.color[0] >> o.color[1] >> o.color[2] >> o.color[3]);
    in >> o.subframes;
    objects.push_back(o);
  }
  std::string rest;
  EXPECT_FALSE(in >> rest) << "after '.': " << rest;
  return objects;
}

TEST(ExportFormats, SceneIsMoveItsTextFormatWithPosesAndPrimitives) {
  const auto files = Render(ExportFormat::kScene, "site.scene");
  ASSERT_EQ(files.size(), 1u);
  std::string name;
  const auto objects = ReadScene(files[0].bytes, &name);
  EXPECT_NE(name.find("MoveIt .scene, the newer format with object poses and subframes"),
            std::string::npos)
      << name;
  EXPECT_NE(name.find("frame world, lengths in m"), std::string::npos) << name;
  ASSERT_EQ(objects.size(), 2u);
  const Expected cylinder = ExpectedOf(Models()[0]);
  EXPECT_EQ(objects[0].id, "model_3");
  EXPECT_EQ(objects[0].shape, "cylinder");
  EXPECT_NEAR(objects[0].dims[0], 2 * kInch, 1e-12);
  EXPECT_NEAR(objects[0].dims[1], 10 * kInch, 1e-12);
  ExpectPose(cylinder, objects[0].t, objects[0].r, "scene cylinder");
  const Expected box = ExpectedOf(Models()[1]);
  EXPECT_EQ(objects[1].id, "model_5");
  EXPECT_EQ(objects[1].shape, "box");
  EXPECT_NEAR(objects[1].dims[0], 6 * kInch, 1e-12);
  EXPECT_NEAR(objects[1].dims[1], 4 * kInch, 1e-12);
  EXPECT_NEAR(objects[1].dims[2], 3 * kInch, 1e-12);
  ExpectPose(box, objects[1].t, objects[1].r, "scene box");
  for (const auto& o : objects) {
    EXPECT_EQ(o.shape_t, Eigen::Vector3d::Zero());
    EXPECT_EQ(o.shape_q, Eigen::Vector4d(0, 0, 0, 1));
    EXPECT_GT(o.color[3], 0);  // MoveIt keeps a colour only when one component is non-zero
    EXPECT_EQ(o.subframes, 0);
  }
}

// ---- URDF ----------------------------------------------------------------------------------

TEST(ExportFormats, UrdfHasAFixedLinkPerModelUnderTheFrame) {
  ExportOptions options;
  options.frame = "table";
  const auto files = Render(ExportFormat::kUrdf, "site.urdf", options);
  ASSERT_EQ(files.size(), 2u);  // the URDF and the box's texture
  EXPECT_EQ(files[1].name, "site_textures/model_5.png");
  EXPECT_EQ(files[1].bytes, Models()[1].record.box.texture_png());
  const std::string& urdf = files[0].bytes;
  EXPECT_NE(urdf.find("<link name=\"table\"/>"), std::string::npos);
  EXPECT_NE(urdf.find("<texture filename=\"site_textures/model_5.png\"/>"), std::string::npos);
  EXPECT_NE(urdf.find("<cylinder radius=\"0.0508\" length=\"0.254\"/>"), std::string::npos);
  const std::regex joint(
      "<joint name=\"(model_\\d+)_joint\" type=\"fixed\">\\s*<parent link=\"table\"/>\\s*"
      "<child link=\"(model_\\d+)\"/>\\s*<origin xyz=\"(\\S+) (\\S+) (\\S+)\" "
      "rpy=\"(\\S+) (\\S+) (\\S+)\"/>");
  int joints = 0;
  for (auto it = std::sregex_iterator(urdf.begin(), urdf.end(), joint);
       it != std::sregex_iterator(); ++it, ++joints) {
    const auto& m = *it;
    EXPECT_EQ(m[1], m[2]);
    const Expected e = ExpectedOf(Models()[joints]);
    EXPECT_EQ(m[1].str(), "model_" + std::to_string(Models()[joints].id));
    ExpectPose(e, {std::stod(m[3]), std::stod(m[4]), std::stod(m[5])},
               FromRpy(std::stod(m[6]), std::stod(m[7]), std::stod(m[8])), m[1]);
  }
  EXPECT_EQ(joints, 2);
  // Collision and visual geometry for each.
  EXPECT_EQ(std::count(urdf.begin(), urdf.end(), '\n') > 0, true);
  for (const char* tag : {"<collision>", "<visual>"}) {
    std::size_t n = 0;
    for (auto p = urdf.find(tag); p != std::string::npos; p = urdf.find(tag, p + 1)) ++n;
    EXPECT_EQ(n, 2u) << tag;
  }
}

// ---- glTF and GLB --------------------------------------------------------------------------

struct Gltf {
  Struct json;
  std::string bin;
};

Gltf ReadGlb(const std::string& bytes) {
  Gltf g;
  std::uint32_t header[3];
  EXPECT_GE(bytes.size(), 20u);
  std::memcpy(header, bytes.data(), 12);
  EXPECT_EQ(std::string(bytes.data(), 4), "glTF");
  EXPECT_EQ(header[1], 2u);
  EXPECT_EQ(header[2], bytes.size());
  std::size_t at = 12;
  while (at + 8 <= bytes.size()) {
    std::uint32_t length;
    std::memcpy(&length, bytes.data() + at, 4);
    const std::string type(bytes.data() + at + 4, 4);
    EXPECT_EQ(length % 4, 0u);
    const std::string chunk = bytes.substr(at + 8, length);
    if (type == "JSON") g.json = ParseJson(chunk);
    if (type == std::string("BIN\0", 4)) g.bin = chunk;
    at += 8 + length;
  }
  EXPECT_EQ(at, bytes.size());
  return g;
}

const google::protobuf::Value& At(const Struct& s, const std::string& key) {
  static const google::protobuf::Value kNone;
  const auto it = s.fields().find(key);
  EXPECT_NE(it, s.fields().end()) << "no " << key;
  return it == s.fields().end() ? kNone : it->second;
}

const Struct& Obj(const google::protobuf::Value& v) { return v.struct_value(); }
const Struct& Item(const Struct& s, const std::string& key, int i) {
  return At(s, key).list_value().values(i).struct_value();
}
double Number(const Struct& s, const std::string& key) { return At(s, key).number_value(); }
int Int(const Struct& s, const std::string& key) {
  return static_cast<int>(At(s, key).number_value());
}
Eigen::VectorXd Numbers(const Struct& s, const std::string& key) {
  const auto& list = At(s, key).list_value();
  Eigen::VectorXd v(list.values_size());
  for (int i = 0; i < list.values_size(); ++i) v[i] = list.values(i).number_value();
  return v;
}

// The accessor's data, as floats (or indices).
template <class T>
std::vector<T> AccessorData(const Gltf& g, int accessor, int components) {
  const Struct& a = Item(g.json, "accessors", accessor);
  const Struct& view = Item(g.json, "bufferViews", Int(a, "bufferView"));
  const std::size_t count = static_cast<std::size_t>(Int(a, "count")) * components;
  std::vector<T> out(count);
  EXPECT_LE(Int(view, "byteOffset") + count * sizeof(T), g.bin.size());
  std::memcpy(out.data(), g.bin.data() + Int(view, "byteOffset"), count * sizeof(T));
  return out;
}

void CheckGltf(const Gltf& g) {
  EXPECT_EQ(At(Obj(At(g.json, "asset")), "version").string_value(), "2.0");
  const auto& nodes = At(g.json, "nodes").list_value();
  ASSERT_EQ(nodes.values_size(), 2);
  // glTF is y up: the output frame's z is glTF's y.
  Eigen::Matrix3d y_up;
  y_up << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  for (int i = 0; i < 2; ++i) {
    const Struct& node = nodes.values(i).struct_value();
    const StoredModel& model = Models()[i];
    EXPECT_EQ(At(node, "name").string_value(), std::to_string(model.id));
    const Eigen::VectorXd t = Numbers(node, "translation");
    const Eigen::VectorXd q = Numbers(node, "rotation");
    const Eigen::Matrix3d r = FromQuaternion(q[0], q[1], q[2], q[3]);
    const Expected e = ExpectedOf(model);
    ExpectPose(e, y_up.transpose() * Eigen::Vector3d(t), y_up.transpose() * r, "glTF node");
    // Extras: type, dimensions, sigmas, provenance.
    const Struct& extras = Obj(At(node, "extras"));
    EXPECT_EQ(Number(extras, "id"), model.id);
    EXPECT_EQ(At(extras, "type").string_value(), e.cylinder ? "cylinder" : "box");
    const Struct& provenance = Obj(At(extras, "provenance"));
    EXPECT_EQ(Number(provenance, "frame_id"), model.record.provenance.frame_id);
    EXPECT_EQ(At(provenance, "calibration_hash").string_value(),
              model.record.provenance.calibration_hash);
    const Struct& measured = Obj(At(extras, "measured"));
    EXPECT_TRUE(Obj(At(measured, "sigma")).fields().count("center"));
    // The mesh, moved by the node, on the model's surface; normals of unit length.
    const Struct& primitive = Item(Item(g.json, "meshes", Int(node, "mesh")), "primitives", 0);
    const Struct& attributes = Obj(At(primitive, "attributes"));
    const auto positions = AccessorData<float>(g, Int(attributes, "POSITION"), 3);
    const auto normals = AccessorData<float>(g, Int(attributes, "NORMAL"), 3);
    const auto indices = AccessorData<std::uint32_t>(g, Int(primitive, "indices"), 1);
    std::vector<Eigen::Vector3d> vertices;
    for (std::size_t k = 0; k < positions.size(); k += 3) {
      const Eigen::Vector3d local(positions[k], positions[k + 1], positions[k + 2]);
      vertices.push_back(y_up.transpose() * (r * local + Eigen::Vector3d(t)));
      const double n = std::sqrt(normals[k] * normals[k] + normals[k + 1] * normals[k + 1] +
                                 normals[k + 2] * normals[k + 2]);
      EXPECT_NEAR(n, 1, 1e-6);
    }
    std::vector<std::array<int, 3>> triangles;
    for (std::size_t k = 0; k < indices.size(); k += 3) {
      triangles.push_back({static_cast<int>(indices[k]), static_cast<int>(indices[k + 1]),
                           static_cast<int>(indices[k + 2])});
    }
    ExpectOnSurface(e, vertices, triangles, "glTF " + std::to_string(model.id));
    EXPECT_EQ(attributes.fields().count("TEXCOORD_0"), e.cylinder ? 0u : 1u);
  }
  // The box's texture embedded as its PNG.
  const Struct& image = Item(g.json, "images", 0);
  EXPECT_EQ(At(image, "mimeType").string_value(), "image/png");
  const Struct& view = Item(g.json, "bufferViews", Int(image, "bufferView"));
  EXPECT_EQ(g.bin.substr(Int(view, "byteOffset"), Int(view, "byteLength")),
            Models()[1].record.box.texture_png());
  EXPECT_NE(At(Obj(At(Obj(At(g.json, "asset")), "extras")), "tessellation")
                .string_value()
                .find("0.001 in"),
            std::string::npos);
}

TEST(ExportFormats, GlbIsBinaryGltfWithNodesMeshesAndTheTexture) {
  const auto files = Render(ExportFormat::kGlb, "site.glb");
  ASSERT_EQ(files.size(), 1u);
  CheckGltf(ReadGlb(files[0].bytes));
}

TEST(ExportFormats, GltfNamesItsBufferBesideIt) {
  const auto files = Render(ExportFormat::kGltf, "site.gltf");
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[1].name, "site.bin");
  Gltf g{ParseJson(files[0].bytes), files[1].bytes};
  const Struct& buffer = Item(g.json, "buffers", 0);
  EXPECT_EQ(At(buffer, "uri").string_value(), "site.bin");
  EXPECT_EQ(Number(buffer, "byteLength"), files[1].bytes.size());
  CheckGltf(g);
}

// ---- OBJ -----------------------------------------------------------------------------------

TEST(ExportFormats, ObjHasAnObjectPerModelWithItsMaterialAndTexture) {
  const auto files = Render(ExportFormat::kObj, "site.obj");
  ASSERT_EQ(files.size(), 3u);
  EXPECT_EQ(files[1].name, "site.mtl");
  EXPECT_EQ(files[2].name, "site_textures/model_5.png");
  EXPECT_NE(files[1].bytes.find("newmtl model_5\n"), std::string::npos);
  EXPECT_NE(files[1].bytes.find("map_Kd site_textures/model_5.png\n"), std::string::npos);
  std::istringstream in(files[0].bytes);
  std::string line;
  std::vector<Eigen::Vector3d> all;
  std::map<std::string, std::vector<std::array<int, 3>>> faces;
  std::string object;
  EXPECT_NE(files[0].bytes.find("mtllib site.mtl"), std::string::npos);
  EXPECT_NE(files[0].bytes.find("within 0.001 in"), std::string::npos);
  while (std::getline(in, line)) {
    std::istringstream l(line);
    std::string kind;
    l >> kind;
    if (kind == "o") l >> object;
    if (kind == "v") {
      Eigen::Vector3d v;
      l >> v.x() >> v.y() >> v.z();
      all.push_back(v);
    }
    if (kind == "f") {
      std::array<int, 3> f;
      for (int& i : f) {
        std::string ref;
        l >> ref;
        i = std::stoi(ref.substr(0, ref.find('/'))) - 1;
      }
      faces[object].push_back(f);
    }
  }
  ASSERT_EQ(faces.size(), 2u);
  for (const StoredModel& m : Models()) {
    const std::string name = "model_" + std::to_string(m.id);
    ExpectOnSurface(ExpectedOf(m), all, faces[name], "OBJ " + name);
  }
}

// ---- STL -----------------------------------------------------------------------------------

TEST(ExportFormats, StlIsBinaryWithOutwardNormals) {
  const auto files = Render(ExportFormat::kStl, "site.stl");
  ASSERT_EQ(files.size(), 1u);
  EXPECT_NE(files[0].bytes.substr(0, 5), "solid");
  EXPECT_NE(files[0].bytes.substr(0, 80).find("within 0.001 in"), std::string::npos);
  const auto triangles = testing::ReadStl(files[0].bytes);
  ASSERT_FALSE(triangles.empty());
  const Expected cylinder = ExpectedOf(Models()[0]);
  const Expected box = ExpectedOf(Models()[1]);
  std::vector<Eigen::Vector3d> vertices[2];
  std::vector<std::array<int, 3>> faces[2];
  for (const auto& t : triangles) {
    const Eigen::Vector3d c = (t.v[0] + t.v[1] + t.v[2]).cast<double>() / 3;
    const int which = std::abs(cylinder.Distance(c)) < std::abs(box.Distance(c)) ? 0 : 1;
    const Expected& e = which == 0 ? cylinder : box;
    // Outward: a step along the normal leaves the solid.
    EXPECT_GT(e.Distance(c + 1e-4 * t.n.cast<double>()), e.Distance(c));
    const int base = static_cast<int>(vertices[which].size());
    for (const auto& v : t.v) vertices[which].push_back(v.cast<double>());
    faces[which].push_back({base, base + 1, base + 2});
  }
  ExpectOnSurface(cylinder, vertices[0], faces[0], "STL cylinder");
  ExpectOnSurface(box, vertices[1], faces[1], "STL box");
  EXPECT_EQ(faces[1].size(), 12u);
}

// ---- JSON ----------------------------------------------------------------------------------

TEST(ExportFormats, JsonListsEveryModelWithItsMeasurementsAndProvenance) {
  const auto files = Render(ExportFormat::kJson, "site.json");
  const Struct json = ParseJson(files[0].bytes);
  EXPECT_EQ(At(json, "format").string_value(), "igms-models");
  EXPECT_EQ(At(json, "units").string_value(), "m");
  const auto& models = At(json, "models").list_value();
  ASSERT_EQ(models.values_size(), 2);
  const Struct& c = models.values(0).struct_value();
  EXPECT_EQ(Number(c, "id"), 3);
  EXPECT_NEAR(Number(c, "radius"), 2 * kInch, 1e-12);
  const Eigen::VectorXd p = Numbers(c, "position");
  EXPECT_LT((Eigen::Vector3d(p) - ExpectedOf(Models()[0]).center).norm(), 1e-9);
  EXPECT_NEAR(Number(Obj(At(c, "measured")), "radius"), 2, 1e-12);
}

// ---- Options -------------------------------------------------------------------------------

TEST(ExportFormats, PaddingMovesEverySurfaceOutByKSigmas) {
  ExportOptions options;
  options.padding_sigmas = 3;
  const auto files = Render(ExportFormat::kStl, "padded.stl", options);
  const Expected padded = ExpectedOf(Models()[0], 3);
  EXPECT_GT(padded.radius, 2 * kInch + 3 * 0.04 * kInch);  // the radius's sigma and more
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> faces;
  for (const auto& t : testing::ReadStl(files[0].bytes)) {
    const Eigen::Vector3d c = (t.v[0] + t.v[1] + t.v[2]).cast<double>() / 3;
    if (std::abs(padded.Distance(c)) > 1e-3) continue;  // the box's
    const int base = static_cast<int>(vertices.size());
    for (const auto& v : t.v) vertices.push_back(v.cast<double>());
    faces.push_back({base, base + 1, base + 2});
  }
  ExpectOnSurface(padded, vertices, faces, "padded cylinder");
  // The box: each face out by K times its position's sigma (docs/exports.md).
  const auto json = ParseJson(Render(ExportFormat::kJson, "p.json", options)[0].bytes);
  const Struct& box = At(json, "models").list_value().values(1).struct_value();
  const Eigen::VectorXd size = Numbers(box, "size");
  const double yaw_sigma = 0.5 * M_PI / 180;
  const double face_x = std::sqrt(0.02 * 0.02 + 0.05 * 0.05 / 4 + std::pow(4.0 / 2 * yaw_sigma, 2));
  EXPECT_NEAR(size[0], (6 + 2 * 3 * face_x) * kInch, 1e-12);
  const double face_z = std::sqrt(0.03 * 0.03 + 0.06 * 0.06 / 4);
  EXPECT_NEAR(size[2], (3 + 2 * 3 * face_z) * kInch, 1e-12);
}

TEST(ExportFormats, BaseTransformAndUnitsPlaceTheModelsInTheRobotsFrame) {
  auto base = ParseBaseTransform("0.5,-0.25,0.1,0.1,-0.2,1.2");
  ASSERT_TRUE(base.ok()) << base.error();
  ExportOptions options;
  options.base_from_world = *base;
  options.frame = "base_link";
  const auto files = Render(ExportFormat::kScene, "b.scene", options);
  std::string name;
  const auto objects = ReadScene(files[0].bytes, &name);
  ASSERT_EQ(objects.size(), 2u);
  ExpectPose(ExpectedOf(Models()[0], 0, *base), objects[0].t, objects[0].r, "based cylinder");
  ExpectPose(ExpectedOf(Models()[1], 0, *base), objects[1].t, objects[1].r, "based box");
  // Millimetres out: the numbers scale, the tolerance stays 0.001 in.
  options = {};
  options.out_units = *ParseLengthUnit("mm");
  const auto mm = ReadScene(Render(ExportFormat::kScene, "mm.scene", options)[0].bytes, &name);
  EXPECT_NEAR(mm[0].dims[0], 50.8, 1e-9);
  EXPECT_NEAR(mm[0].t.x(), 254, 1e-9);
  EXPECT_FALSE(ParseBaseTransform("1,2,3").ok());
  EXPECT_FALSE(ParseBaseTransform("1,2,3,4,5,x").ok());
  EXPECT_FALSE(ParseLengthUnit("furlong"));
}

// ---- Bad input -----------------------------------------------------------------------------

TEST(ExportFormats, ANonFiniteModelIsRefusedByIdAndNothingIsWritten) {
  std::vector<StoredModel> models = Models();
  models[1].record.box.mutable_center()->set_y(std::numeric_limits<double>::infinity());
  const auto dir = igms::testing::FreshTempDir("export-refused");
  auto all = WriteAllExports(models, {}, dir.string());
  ASSERT_FALSE(all.ok());
  EXPECT_NE(all.error().find("model 5: box.center.y is infinite"), std::string::npos)
      << all.error();
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  models[1] = ExportBox(5);
  models[0].record.cylinder.set_radius(std::nan(""));
  auto one = WriteExport(models, ExportFormat::kUrdf, {}, (dir / "x.urdf").string());
  ASSERT_FALSE(one.ok());
  EXPECT_NE(one.error().find("model 3: cylinder.radius is NaN"), std::string::npos);
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  std::filesystem::remove_all(dir);
}

TEST(ExportFormats, AnEmptyDatabaseGivesEmptyFilesExceptSTL) {
  for (ExportFormat f : AllExportFormats()) {
    auto files = RenderExport({}, f, {}, std::string("empty") + ExportExtension(f));
    if (f == ExportFormat::kStl) {
      ASSERT_FALSE(files.ok());
      EXPECT_NE(files.error().find("STL has no empty form"), std::string::npos);
      continue;
    }
    ASSERT_TRUE(files.ok()) << ExportFormatName(f) << ": " << files.error();
    // OBJ names its (empty) MTL; the others are one file.
    EXPECT_EQ(files->size(), f == ExportFormat::kObj ? 2u : 1u) << ExportFormatName(f);
  }
  std::string name;
  EXPECT_TRUE(
      ReadScene(RenderExport({}, ExportFormat::kScene, {}, "e.scene")->at(0).bytes, &name).empty());
  const Gltf g = ReadGlb(RenderExport({}, ExportFormat::kGlb, {}, "e.glb")->at(0).bytes);
  EXPECT_EQ(g.json.fields().count("nodes"), 0u);
  EXPECT_TRUE(g.bin.empty());
}

TEST(ExportFormats, WritesAreWholeFilesRenamedIntoPlace) {
  const auto dir = igms::testing::FreshTempDir("export-all");
  auto report = WriteAllExports(Models(), {}, dir.string());
  ASSERT_TRUE(report.ok()) << report.error();
  EXPECT_EQ(report->written.size(), AllExportFormats().size());
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  }
  EXPECT_TRUE(std::filesystem::exists(dir / "models_textures/model_5.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "models.bin"));
  // A folder that cannot be made: a clear error, no file.
  auto bad = WriteExport(Models(), ExportFormat::kJson, {},
                         (dir / "models.json" / "below-a-file.json").string());
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("cannot create the folder " + (dir / "models.json").string()),
            std::string::npos)
      << bad.error();
  // Emptied, the folder loses its STL, which would no longer match.
  report = WriteAllExports({}, {}, dir.string());
  ASSERT_TRUE(report.ok());
  EXPECT_FALSE(std::filesystem::exists(dir / "models.stl"));
  ASSERT_EQ(report->skipped.size(), 1u);
  std::filesystem::remove_all(dir);
}

TEST(ExportFormats, TessellationUsesTheFewestSidesWithinTheTolerance) {
  // A 2 in pipe in metres: sagitta r (1 - cos(pi / n)) under 0.001 in.
  ExportOptions options;
  const auto g = ReadGlb(Render(ExportFormat::kGlb, "t.glb", options)[0].bytes);
  const Struct& extras = Obj(At(Item(g.json, "nodes", 0), "extras"));
  (void)extras;
  const double r = 2, tol = 0.001;
  const int n = static_cast<int>(std::ceil(M_PI / std::acos(1 - tol / r)));
  EXPECT_LT(r * (1 - std::cos(M_PI / n)), tol);
  EXPECT_GE(r * (1 - std::cos(M_PI / (n - 1))), tol);
  const auto& accessor = Item(g.json, "accessors", 0);
  EXPECT_EQ(Int(accessor, "count"), 2 * (n + 1) + 2 * (n + 1));  // side ring and two ends
}

// ---- igms locate --json --------------------------------------------------------------------

TEST(ExportFormats, ReadsTheLinesOfIgmsLocateJson) {
  const std::string text =
      "{\"found\": true, \"type\": \"cylinder\", \"center\": [1, 2, 3], \"axis\": [0, 0, 1], "
      "\"radius\": 0.5, \"height\": 4, \"sigma\": {\"center\": [0.01, 0.01, 0.02], "
      "\"radius\": 0.003, \"height\": 0.02}, \"rms_px\": [0.4, 0.5], \"outline_samples\": 80, "
      "\"boundary_pixels\": 500, \"ssd_rms\": 2.1, \"elapsed_ms\": 35}\n"
      "\n"
      "{\"found\": false, \"type\": \"box\", \"reason\": \"FAILURE_FIT_FAILED\", \"detail\": "
      "\"x\"}\n"
      "{\"found\": true, \"type\": \"box\", \"min\": [0, 0, 0], \"max\": [2, 1, 1], \"center\": "
      "[1, 0.5, 0.5], \"size\": [2, 1, 1], \"yaw_deg\": 10, \"texture_rect\": [1, 2, 30, 40], "
      "\"sigma\": {\"min\": [0, 0, 0], \"max\": [0, 0, 0], \"center\": [0.01, 0.01, 0.01], "
      "\"size\": [0.02, 0.02, 0.02], \"yaw_deg\": 0.3}, \"rms_px\": [0.4, 0.5], "
      "\"outline_samples\": 80, \"boundary_pixels\": 500, \"ssd_rms\": 2.1, \"elapsed_ms\": 35}\n";
  auto models = ReadLocateJson(text);
  ASSERT_TRUE(models.ok()) << models.error();
  ASSERT_EQ(models->size(), 2u);
  EXPECT_EQ((*models)[0].id, 1);
  EXPECT_EQ((*models)[0].record.cylinder.radius(), 0.5);
  EXPECT_EQ((*models)[1].id, 2);
  EXPECT_EQ((*models)[1].record.box.yaw_deg(), 10);
  EXPECT_EQ((*models)[1].record.box.size_sigma().x(), 0.02);
  auto bad = ReadLocateJson("{\"found\": true, \"type\": \"cylinder\"}\nnot json\n");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("line 1"), std::string::npos) << bad.error();
}

}  // namespace
}  // namespace igms::control
