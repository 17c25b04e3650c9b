// The writers of every format, from the solids (solids.h). Each format's layout is described
// in docs/exports.md; the comments here say why where the format leaves a choice.
#include "control/export/formats.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "common/base/json.h"

namespace igms::control::exporting {

namespace {

std::string Stem(const std::string& main_name) {
  return std::filesystem::path(main_name).stem().string();
}

std::string TextureName(const std::string& main_name, const Solid& s) {
  return Stem(main_name) + "_textures/" + s.name + ".png";
}

const std::string& TexturePng(const Solid& s) { return s.model->record.box.texture_png(); }

std::string Vec(const Eigen::Vector3d& v, const char* sep = " ") {
  return Num(v.x()) + sep + Num(v.y()) + sep + Num(v.z());
}

std::string JsonVec(const Eigen::Vector3d& v) { return "[" + Vec(v, ", ") + "]"; }

std::string JsonVec(const object::Vec3& v) { return JsonVec(Eigen::Vector3d(v.x(), v.y(), v.z())); }

// Rotation as (x, y, z, w), w >= 0 so the text is one of the two equal quaternions.
Eigen::Vector4d Quaternion(const Eigen::Matrix3d& r) {
  Eigen::Quaterniond q(r);
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1;
  return q.coeffs();
}

std::string TessellationNote(const ExportOptions& o) {
  return "cylinders tessellated within " + Num(kTessellationToleranceInches) + " in (" +
         Num(ToleranceOut(o)) + " " + o.out_units.name + ") of the true surface";
}

std::string FrameNote(const ExportOptions& o) {
  return "frame " + o.frame + ", lengths in " + o.out_units.name + ", padding " +
         Num(o.padding_sigmas) + " sigma";
}

// What a model is, in world units as measured (before padding), and where it came from:
// the JSON export's model entries and glTF's node extras.
std::string ModelJson(const Solid& s, const ExportOptions& o) {
  const StoredModel& m = *s.model;
  const ModelRecord& r = m.record;
  std::ostringstream j;
  j << "{\"id\": " << m.id << ", \"name\": " << JsonQuote(s.name) << ", \"type\": \""
    << (s.cylinder ? "cylinder" : "box") << "\"";
  if (s.cylinder) {
    j << ", \"radius\": " << Num(s.radius) << ", \"height\": " << Num(s.height);
  } else {
    j << ", \"size\": " << JsonVec(s.size);
  }
  const Eigen::Vector4d q = Quaternion(s.pose.linear());
  j << ", \"position\": " << JsonVec(Eigen::Vector3d(s.pose.translation()))
    << ", \"orientation\": [" << Num(q.x()) << ", " << Num(q.y()) << ", " << Num(q.z()) << ", "
    << Num(q.w()) << "]";
  j << ", \"measured\": {\"units\": " << JsonQuote(o.world_units.name);
  if (s.cylinder) {
    const auto& c = r.cylinder;
    j << ", \"center\": " << JsonVec(c.center()) << ", \"axis\": " << JsonVec(c.axis())
      << ", \"radius\": " << Num(c.radius()) << ", \"height\": " << Num(c.height())
      << ", \"sigma\": {\"center\": " << JsonVec(c.center_sigma())
      << ", \"radius\": " << Num(c.radius_sigma()) << ", \"height\": " << Num(c.height_sigma())
      << "}";
  } else {
    const auto& b = r.box;
    j << ", \"center\": " << JsonVec(b.center()) << ", \"size\": " << JsonVec(b.size())
      << ", \"yaw_deg\": " << Num(b.yaw_deg())
      << ", \"sigma\": {\"center\": " << JsonVec(b.center_sigma())
      << ", \"size\": " << JsonVec(b.size_sigma()) << ", \"yaw_deg\": " << Num(b.yaw_sigma_deg())
      << "}";
    if (!b.texture_png().empty()) {
      j << ", \"texture_rect\": [" << b.texture_u0() << ", " << b.texture_v0() << ", "
        << b.texture_u1() << ", " << b.texture_v1() << "]";
    }
  }
  j << "}";
  const ModelProvenance& p = r.provenance;
  j << ", \"provenance\": {\"frame_id\": " << p.frame_id
    << ", \"calibration_hash\": " << JsonQuote(p.calibration_hash)
    << ", \"left_capture_unix_ns\": " << p.left_capture_unix_ns
    << ", \"right_capture_unix_ns\": " << p.right_capture_unix_ns
    << ", \"added_unix_ns\": " << m.added_unix_ns << ", \"session_id\": " << m.session_id
    << ", \"range\": " << Num(p.range) << ", \"rms_px\": [" << Num(p.rms_left_px) << ", "
    << Num(p.rms_right_px) << "], \"servers\": [";
  for (std::size_t i = 0; i < p.servers.size(); ++i) {
    j << (i ? ", " : "") << "{\"name\": " << JsonQuote(p.servers[i].name)
      << ", \"program\": " << JsonQuote(p.servers[i].program)
      << ", \"version\": " << JsonQuote(p.servers[i].version) << "}";
  }
  j << "]}}";
  return j.str();
}

// ---- MoveIt's .scene ----------------------------------------------------------------------
// As PlanningScene::saveGeometryToStream writes it in MoveIt 1 (Noetic) and MoveIt 2, the
// format with object poses and subframes ("new scene format"): the scene's name; per object
// "* id", its pose (x y z / qx qy qz qw), its shape count, per shape geometric_shapes'
// text (type line, dimensions line), its pose relative to the object and its colour, then
// its subframe count; "." ends the file. The name line carries the version, units and frame
// (a reader takes the whole line as the name; there is no comment syntax).
std::string Scene(const std::vector<Solid>& solids, const ExportOptions& o) {
  std::ostringstream s;
  s << o.name << " (MoveIt .scene, the newer format with object poses and subframes: MoveIt 1 "
    << "Noetic, MoveIt 2; " << FrameNote(o) << ")\n";
  for (const Solid& solid : solids) {
    s << "* " << solid.name << "\n";
    const Eigen::Vector4d q = Quaternion(solid.pose.linear());
    s << Vec(solid.pose.translation()) << "\n"
      << Num(q.x()) << " " << Num(q.y()) << " " << Num(q.z()) << " " << Num(q.w()) << "\n";
    s << "1\n";
    if (solid.cylinder) {
      s << "cylinder\n" << Num(solid.radius) << " " << Num(solid.height) << "\n";
    } else {
      s << "box\n" << Vec(solid.size) << "\n";
    }
    s << "0 0 0\n0 0 0 1\n";
    s << (solid.cylinder ? "0.6 0.6 0.65 1" : "0.7 0.55 0.35 1") << "\n";
    s << "0\n";
  }
  s << ".\n";
  return s.str();
}

// ---- URDF ----------------------------------------------------------------------------------
// One fixed link per model under the frame's link; collision and visual geometry are URDF's
// own box and cylinder (exact, not meshes); a box's texture is its visual material's.
std::vector<ExportFile> Urdf(const std::vector<Solid>& solids, const ExportOptions& o,
                             const std::string& main_name) {
  std::vector<ExportFile> files(1);
  files[0].name = main_name;
  std::ostringstream u;
  u << "<?xml version=\"1.0\"?>\n"
    << "<!-- igms export: " << FrameNote(o) << " -->\n"
    << "<robot name=\"" << o.name << "\">\n"
    << "  <link name=\"" << o.frame << "\"/>\n";
  for (const Solid& s : solids) {
    std::string geometry;
    if (s.cylinder) {
      geometry = "<cylinder radius=\"" + Num(s.radius) + "\" length=\"" + Num(s.height) + "\"/>";
    } else {
      geometry = "<box size=\"" + Vec(s.size) + "\"/>";
    }
    u << "  <link name=\"" << s.name << "\">\n"
      << "    <visual>\n      <geometry>" << geometry << "</geometry>\n"
      << "      <material name=\"" << s.name << "_material\">\n"
      << "        <color rgba=\"" << (s.cylinder ? "0.6 0.6 0.65 1" : "0.7 0.55 0.35 1")
      << "\"/>\n";
    if (s.textured) {
      const std::string texture = TextureName(main_name, s);
      u << "        <texture filename=\"" << texture << "\"/>\n";
      files.push_back({texture, TexturePng(s)});
    }
    u << "      </material>\n    </visual>\n"
      << "    <collision>\n      <geometry>" << geometry << "</geometry>\n    </collision>\n"
      << "  </link>\n";
    const Eigen::Vector3d rpy = RollPitchYaw(s.pose.linear());
    u << "  <joint name=\"" << s.name << "_joint\" type=\"fixed\">\n"
      << "    <parent link=\"" << o.frame << "\"/>\n    <child link=\"" << s.name << "\"/>\n"
      << "    <origin xyz=\"" << Vec(s.pose.translation()) << "\" rpy=\"" << Vec(rpy)
      << "\"/>\n  </joint>\n";
  }
  u << "</robot>\n";
  files[0].bytes = u.str();
  return files;
}

// ---- glTF 2.0 ------------------------------------------------------------------------------
// One buffer; per model a mesh (POSITION, NORMAL, TEXCOORD_0 for a textured box, indices),
// a node named by the model's id with its pose as translation and rotation, and extras.
// glTF is y up: the output frame (z up) turns by -90 degrees about x.

void Append(std::string& bin, const void* data, std::size_t bytes) {
  bin.append(static_cast<const char*>(data), bytes);
  while (bin.size() % 4) bin.push_back('\0');
}

struct GltfParts {
  std::string json;
  std::string bin;
};

GltfParts Gltf(const std::vector<Solid>& solids, const ExportOptions& o,
               const std::string& buffer_uri) {
  Eigen::Matrix3d y_up;
  y_up << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  GltfParts parts;
  std::ostringstream views, accessors, meshes, nodes, materials, textures, images;
  int view_count = 0, accessor_count = 0, image_count = 0;
  auto add_view = [&](const void* data, std::size_t bytes, int target) {
    const std::size_t offset = parts.bin.size();
    Append(parts.bin, data, bytes);
    views << (view_count ? ",\n" : "") << "{\"buffer\": 0, \"byteOffset\": " << offset
          << ", \"byteLength\": " << bytes;
    if (target) views << ", \"target\": " << target;
    views << "}";
    return view_count++;
  };
  auto add_accessor = [&](int view, int component, std::size_t count, const char* type,
                          const std::string& bounds) {
    accessors << (accessor_count ? ",\n" : "") << "{\"bufferView\": " << view
              << ", \"componentType\": " << component << ", \"count\": " << count
              << ", \"type\": \"" << type << "\"" << bounds << "}";
    return accessor_count++;
  };
  // Material 0: untextured cylinders and boxes; then one per textured box.
  materials << "{\"name\": \"igms_model\", \"pbrMetallicRoughness\": {\"baseColorFactor\": "
               "[0.6, 0.6, 0.65, 1], \"metallicFactor\": 0, \"roughnessFactor\": 0.8}}";
  int material_count = 1;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    const Solid& s = solids[i];
    const Mesh mesh = MeshOf(s);
    Eigen::Vector3f lo = mesh.positions[0], hi = mesh.positions[0];
    for (const auto& p : mesh.positions) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    // The bounds exactly as the float32 data holds them: readers compare them to it.
    auto exact = [](float v) {
      char text[40];
      std::snprintf(text, sizeof text, "%.17g", static_cast<double>(v));
      return std::string(text);
    };
    const std::string bounds = ", \"min\": [" + exact(lo.x()) + ", " + exact(lo.y()) + ", " +
                               exact(lo.z()) + "], \"max\": [" + exact(hi.x()) + ", " +
                               exact(hi.y()) + ", " + exact(hi.z()) + "]";
    const std::size_t n = mesh.positions.size();
    const int pos =
        add_accessor(add_view(mesh.positions.data(), n * 12, 34962), 5126, n, "VEC3", bounds);
    const int nor = add_accessor(add_view(mesh.normals.data(), n * 12, 34962), 5126, n, "VEC3", "");
    int uv = -1;
    int material = 0;
    if (s.textured) {
      uv = add_accessor(add_view(mesh.uvs.data(), n * 8, 34962), 5126, n, "VEC2", "");
      const std::string& png = TexturePng(s);
      const int image_view = add_view(png.data(), png.size(), 0);
      images << (image_count ? ",\n" : "") << "{\"name\": " << JsonQuote(s.name)
             << ", \"bufferView\": " << image_view << ", \"mimeType\": \"image/png\"}";
      textures << (image_count ? ",\n" : "") << "{\"sampler\": 0, \"source\": " << image_count
               << "}";
      materials << ",\n{\"name\": " << JsonQuote(s.name + "_texture")
                << ", \"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": " << image_count
                << "}, \"metallicFactor\": 0, \"roughnessFactor\": 0.8}}";
      ++image_count;
      material = material_count++;
    }
    const int idx = add_accessor(add_view(mesh.indices.data(), mesh.indices.size() * 4, 34963),
                                 5125, mesh.indices.size(), "SCALAR", "");
    meshes << (i ? ",\n" : "") << "{\"name\": " << JsonQuote(s.name)
           << ", \"primitives\": [{\"attributes\": {\"POSITION\": " << pos
           << ", \"NORMAL\": " << nor;
    if (uv >= 0) meshes << ", \"TEXCOORD_0\": " << uv;
    meshes << "}, \"indices\": " << idx << ", \"material\": " << material << "}]}";
    const Eigen::Vector3d t = y_up * s.pose.translation();
    const Eigen::Vector4d q = Quaternion(y_up * s.pose.linear());
    nodes << (i ? ",\n" : "") << "{\"name\": " << JsonQuote(std::to_string(s.model->id))
          << ", \"mesh\": " << i << ", \"translation\": " << JsonVec(t) << ", \"rotation\": ["
          << Num(q.x()) << ", " << Num(q.y()) << ", " << Num(q.z()) << ", " << Num(q.w())
          << "], \"extras\": " << ModelJson(s, o) << "}";
  }
  std::ostringstream j;
  j << "{\"asset\": {\"version\": \"2.0\", \"generator\": \"igms export\", \"extras\": "
       "{\"frame\": "
    << JsonQuote(o.frame) << ", \"units\": " << JsonQuote(o.out_units.name)
    << ", \"axes\": \"y up: the frame's (x, y, z) is glTF's (x, -z, y)\""
    << ", \"padding_sigmas\": " << Num(o.padding_sigmas)
    << ", \"tessellation\": " << JsonQuote(TessellationNote(o)) << "}},\n"
    << "\"scene\": 0,\n\"scenes\": [{\"name\": " << JsonQuote(o.name);
  if (!solids.empty()) {
    j << ", \"nodes\": [";
    for (std::size_t i = 0; i < solids.size(); ++i) j << (i ? ", " : "") << i;
    j << "]";
  }
  j << "}]";
  if (!solids.empty()) {
    j << ",\n\"nodes\": [" << nodes.str() << "],\n\"meshes\": [" << meshes.str()
      << "],\n\"materials\": [" << materials.str() << "],\n\"accessors\": [" << accessors.str()
      << "],\n\"bufferViews\": [" << views.str()
      << "],\n\"buffers\": [{\"byteLength\": " << parts.bin.size();
    if (!buffer_uri.empty()) j << ", \"uri\": " << JsonQuote(buffer_uri);
    j << "}]";
    if (image_count) {
      j << ",\n\"samplers\": [{\"magFilter\": 9729, \"minFilter\": 9987, \"wrapS\": 33071, "
           "\"wrapT\": 33071}],\n\"textures\": ["
        << textures.str() << "],\n\"images\": [" << images.str() << "]";
    }
  }
  j << "\n}\n";
  parts.json = j.str();
  return parts;
}

void PutU32(std::string& out, std::uint32_t v) {
  char b[4];
  std::memcpy(b, &v, 4);  // little-endian machines only, as glTF and STL are
  out.append(b, 4);
}

std::string Glb(GltfParts parts) {
  while (parts.json.size() % 4) parts.json.push_back(' ');
  std::string out;
  const std::size_t total =
      12 + 8 + parts.json.size() + (parts.bin.empty() ? 0 : 8 + parts.bin.size());
  out.append("glTF", 4);
  PutU32(out, 2);
  PutU32(out, static_cast<std::uint32_t>(total));
  PutU32(out, static_cast<std::uint32_t>(parts.json.size()));
  out.append("JSON", 4);
  out += parts.json;
  if (!parts.bin.empty()) {
    PutU32(out, static_cast<std::uint32_t>(parts.bin.size()));
    out.append("BIN\0", 4);
    out += parts.bin;
  }
  return out;
}

// A space and the number: std::to_chars, as printf's %g or %f, at several times its speed
// (an OBJ of 10,000 models is hundreds of megabytes of text).
void AppendNumber(std::string& out, double value, std::chars_format format, int precision) {
  char text[64];
  text[0] = ' ';
  if (value == 0) value = 0;  // no "-0"
  const auto end = std::to_chars(text + 1, text + sizeof text, value, format, precision).ptr;
  out.append(text, end);
}

void AppendIndex(std::string& out, std::size_t value) {
  char text[24];
  const auto end = std::to_chars(text, text + sizeof text, value).ptr;
  out.append(text, end);
}

// ---- OBJ and MTL ---------------------------------------------------------------------------
// One object per model, vertices in the output frame (z up, as the site's); one material per
// textured box (map_Kd its PNG), one for the rest.
std::vector<ExportFile> Obj(const std::vector<Solid>& solids, const ExportOptions& o,
                            const std::string& main_name) {
  std::vector<ExportFile> files(2);
  const std::string mtl_name = Stem(main_name) + ".mtl";
  files[0].name = main_name;
  files[1].name = mtl_name;
  std::string obj;
  obj.reserve(solids.size() * 4096);
  obj += "# igms export: " + std::to_string(solids.size()) + " models; " + FrameNote(o) + "; " +
         TessellationNote(o) + "\n";
  obj += "mtllib " + mtl_name + "\n";
  std::string mtl = "# igms export\nnewmtl igms_model\nKd 0.6 0.6 0.65\nKa 0 0 0\nd 1\n";
  std::size_t base = 1;  // OBJ counts from 1, across the file
  for (const Solid& s : solids) {
    const Mesh mesh = MeshOf(s);
    obj += "o " + s.name + "\n";
    const Eigen::Matrix3d r = s.pose.linear();
    for (const auto& p : mesh.positions) {
      const Eigen::Vector3d w = s.pose * p.cast<double>();
      obj += "v";
      for (int k = 0; k < 3; ++k) AppendNumber(obj, w[k], std::chars_format::general, 9);
      obj += '\n';
    }
    for (const auto& n : mesh.normals) {
      const Eigen::Vector3d w = r * n.cast<double>();
      obj += "vn";
      for (int k = 0; k < 3; ++k) AppendNumber(obj, w[k], std::chars_format::fixed, 6);
      obj += '\n';
    }
    for (const auto& uv : mesh.uvs) {
      // OBJ's v runs up from the image's bottom.
      obj += "vt";
      AppendNumber(obj, uv.x(), std::chars_format::fixed, 6);
      AppendNumber(obj, 1 - uv.y(), std::chars_format::fixed, 6);
      obj += '\n';
    }
    if (s.textured) {
      const std::string texture = TextureName(main_name, s);
      mtl += "newmtl " + s.name + "\nKd 1 1 1\nKa 0 0 0\nd 1\nmap_Kd " + texture + "\n";
      files.push_back({texture, TexturePng(s)});
      obj += "usemtl " + s.name + "\n";
    } else {
      obj += "usemtl igms_model\n";
    }
    for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
      obj += "f";
      for (int k = 0; k < 3; ++k) {
        // v/vt/vn: each vertex has its own texture coordinate and normal.
        const std::size_t v = base + mesh.indices[i + k];
        obj += ' ';
        AppendIndex(obj, v);
        obj += '/';
        AppendIndex(obj, v);
        obj += '/';
        AppendIndex(obj, v);
      }
      obj += '\n';
    }
    base += mesh.positions.size();
  }
  files[0].bytes = std::move(obj);
  files[1].bytes = std::move(mtl);
  return files;
}

// ---- binary STL ----------------------------------------------------------------------------
// An 80-byte header (which must not begin with "solid", or readers take it for ASCII STL),
// the triangle count, then per triangle its normal, three vertices and a zero attribute.
std::string Stl(const std::vector<Solid>& solids, const ExportOptions& o) {
  std::size_t triangles = 0;
  std::vector<Mesh> meshes;
  meshes.reserve(solids.size());
  for (const Solid& s : solids) {
    meshes.push_back(MeshOf(s));
    triangles += meshes.back().indices.size() / 3;
  }
  std::string out;
  out.reserve(84 + triangles * 50);
  std::string header =
      "IGMS export, " + o.out_units.name + ", frame " + o.frame + ", cylinders within 0.001 in";
  header.resize(80, ' ');
  out += header;
  PutU32(out, static_cast<std::uint32_t>(triangles));
  for (std::size_t m = 0; m < solids.size(); ++m) {
    const Solid& s = solids[m];
    const Mesh& mesh = meshes[m];
    for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
      Eigen::Vector3f v[3];
      for (int k = 0; k < 3; ++k) {
        v[k] = (s.pose * mesh.positions[mesh.indices[i + k]].cast<double>()).cast<float>();
      }
      Eigen::Vector3f n = (v[1] - v[0]).cross(v[2] - v[0]);
      const float length = n.norm();
      n = length > 0 ? Eigen::Vector3f(n / length) : Eigen::Vector3f::Zero();
      float record[12] = {n.x(),    n.y(),    n.z(),    v[0].x(), v[0].y(), v[0].z(),
                          v[1].x(), v[1].y(), v[1].z(), v[2].x(), v[2].y(), v[2].z()};
      out.append(reinterpret_cast<const char*>(record), sizeof record);
      out.append(2, '\0');
    }
  }
  return out;
}

// ---- JSON ----------------------------------------------------------------------------------
std::string Json(const std::vector<Solid>& solids, const ExportOptions& o) {
  std::ostringstream j;
  const Eigen::Vector3d rpy = RollPitchYaw(o.base_from_world.linear());
  j << "{\"format\": \"igms-models\", \"version\": 1, \"name\": " << JsonQuote(o.name)
    << ", \"frame\": " << JsonQuote(o.frame) << ", \"units\": " << JsonQuote(o.out_units.name)
    << ", \"world_units\": " << JsonQuote(o.world_units.name) << ", \"base_from_world\": {\"xyz\": "
    << JsonVec(Eigen::Vector3d(o.base_from_world.translation())) << ", \"rpy\": " << JsonVec(rpy)
    << "}, \"padding_sigmas\": " << Num(o.padding_sigmas) << ",\n\"models\": [";
  for (std::size_t i = 0; i < solids.size(); ++i) {
    j << (i ? ",\n" : "\n") << ModelJson(solids[i], o);
  }
  j << "\n]}\n";
  return j.str();
}

}  // namespace

Result<std::vector<ExportFile>> Render(const std::vector<Solid>& solids, ExportFormat format,
                                       const ExportOptions& options, const std::string& main_name) {
  switch (format) {
    case ExportFormat::kScene:
      return std::vector<ExportFile>{{main_name, Scene(solids, options)}};
    case ExportFormat::kUrdf:
      return Urdf(solids, options, main_name);
    case ExportFormat::kGltf: {
      const std::string bin = Stem(main_name) + ".bin";
      GltfParts parts = Gltf(solids, options, bin);
      std::vector<ExportFile> files{{main_name, std::move(parts.json)}};
      if (!solids.empty()) files.push_back({bin, std::move(parts.bin)});
      return files;
    }
    case ExportFormat::kGlb:
      return std::vector<ExportFile>{{main_name, Glb(Gltf(solids, options, ""))}};
    case ExportFormat::kObj:
      return Obj(solids, options, main_name);
    case ExportFormat::kStl:
      if (solids.empty()) {
        return ErrorMessage{"no models: STL has no empty form, so no STL was written"};
      }
      return std::vector<ExportFile>{{main_name, Stl(solids, options)}};
    case ExportFormat::kJson:
      return std::vector<ExportFile>{{main_name, Json(solids, options)}};
  }
  return ErrorMessage{"unknown format"};
}

}  // namespace igms::control::exporting
