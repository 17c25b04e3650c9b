// Exports of the geometric database (docs/exports.md): the operator's models in the formats
// robots and CAD tools load, so that a planner can use them (Cooke, *Interactive Graphical
// Model Building using Virtual Reality* (1993), section 2.3: the database is for robots).
//
//   ExportOptions options;                     // metres from inches, frame "world"
//   auto files = RenderExport(models, ExportFormat::kUrdf, options, "site.urdf");
//   auto written = WriteExport(models, ExportFormat::kGlb, options, "out/site.glb");
//   auto all = WriteAllExports(models, options, "out/");   // out/models.* in every format
//
// - The models are values (the database's StoredModel); the command reads them from a
//   database (GeometricDatabase::OpenReadOnly) or from `igms locate --json` lines.
// - A model with a non-finite or impossible value is refused, naming its id, before
//   anything is written.
// - Nothing is half-written: each file goes to a temporary name in its folder, then is
//   renamed; the main file last, so a reader of it finds what it names.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "control/database/geometric_database.h"

namespace igms::control {

enum class ExportFormat { kScene, kUrdf, kGltf, kGlb, kObj, kStl, kJson };

// "scene", "urdf", "gltf", "glb", "obj", "stl", "json"; nullopt for another name.
std::optional<ExportFormat> ParseExportFormat(const std::string& name);
const char* ExportFormatName(ExportFormat format);
const char* ExportExtension(ExportFormat format);  // ".scene", ".urdf", ...
std::vector<ExportFormat> AllExportFormats();

// A length unit, as metres per unit.
struct LengthUnit {
  std::string name;  // "in", "m", "mm", "cm", "ft"
  double metres = 1;
};
// "in" (or "inch", "inches"), "ft", "m" (or "metre(s)", "meter(s)"), "cm", "mm".
std::optional<LengthUnit> ParseLengthUnit(const std::string& name);

struct ExportOptions {
  // The database's lengths are the calibration's world units (inches on the thesis's
  // testbed); files are written in out_units.
  LengthUnit world_units{"in", 0.0254};
  LengthUnit out_units{"m", 1.0};
  // base_from_world maps the site's frame (z up) to the robot's base frame, the frame every
  // file is written in: translation in out_units. Identity: the site's frame itself.
  Eigen::Isometry3d base_from_world = Eigen::Isometry3d::Identity();
  std::string frame = "world";  // the frame's name (URDF root link, .scene and glTF notes)
  // Each surface moves out by K standard deviations of its position (docs/exports.md), so a
  // planner keeps clear of where the object may be; 0: the models as measured.
  double padding_sigmas = 0;
  std::string name = "igms_models";  // the scene's, robot's or asset's name
};

// "x,y,z,roll,pitch,yaw" (metres or out_units, radians; R = Rz(yaw) Ry(pitch) Rx(roll), as
// URDF's rpy) as a transform.
Result<Eigen::Isometry3d> ParseBaseTransform(const std::string& text);

// The largest distance of a tessellated cylinder's surface from the true one.
inline constexpr double kTessellationToleranceInches = 0.001;

// One file of an export: its name relative to the main file's folder, and its bytes.
struct ExportFile {
  std::string name;
  std::string bytes;
};

// An export in memory: files[0] is the main file (`main_name`, a file name without folders);
// the rest are what it names (the glTF buffer, OBJ's MTL, textures). Fails for a refused
// model, or an empty STL (STL has no empty form).
Result<std::vector<ExportFile>> RenderExport(const std::vector<StoredModel>& models,
                                             ExportFormat format, const ExportOptions& options,
                                             const std::string& main_name);

// Renders and writes `out` (and its companions beside it), atomically per file. The paths
// written, the main file first.
Result<std::vector<std::string>> WriteExport(const std::vector<StoredModel>& models,
                                             ExportFormat format, const ExportOptions& options,
                                             const std::string& out);

struct AllExportsReport {
  std::vector<std::string> written;  // main files, in AllExportFormats() order
  std::vector<std::string> skipped;  // why a format was not written (an empty STL)
};
// Every format into `folder` (made when missing) as models.<extension>. A refused model
// fails the whole export before anything is written.
Result<AllExportsReport> WriteAllExports(const std::vector<StoredModel>& models,
                                         const ExportOptions& options, const std::string& folder);

// Why the model cannot be exported ("model 12: cylinder.radius is NaN"), or nullopt.
std::optional<std::string> CheckExportModel(const StoredModel& model);

// The models of `igms locate --json` output, one JSON object per line (blank lines and
// not-found results are skipped); the n-th found result gets id n (from 1). An error names
// the line.
Result<std::vector<StoredModel>> ReadLocateJson(const std::string& text);

}  // namespace igms::control
