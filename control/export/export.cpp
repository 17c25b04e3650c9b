#include "control/export/export.h"

#include <fcntl.h>
#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "control/export/formats.h"
#include "control/export/solids.h"

namespace igms::control {

namespace fs = std::filesystem;

namespace {

// Writes `bytes` to a temporary file beside `path`; the temporary's name.
Result<std::string> WriteTemporary(const fs::path& path, const std::string& bytes) {
  std::error_code error;
  fs::create_directories(path.parent_path(), error);
  if (error) {
    return ErrorMessage{"cannot create the folder " + path.parent_path().string() + ": " +
                        error.message()};
  }
  const std::string temporary =
      (path.parent_path() / ("." + path.filename().string() + ".tmp-" + std::to_string(getpid())))
          .string();
  const int fd = open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    return ErrorMessage{"cannot write " + path.string() + ": " +
                        std::generic_category().message(errno)};
  }
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = std::generic_category().message(errno);
      close(fd);
      unlink(temporary.c_str());
      return ErrorMessage{"cannot write " + path.string() + ": " + why};
    }
    done += static_cast<std::size_t>(n);
  }
  if (close(fd) != 0) {
    const std::string why = std::generic_category().message(errno);
    unlink(temporary.c_str());
    return ErrorMessage{"cannot write " + path.string() + ": " + why};
  }
  return temporary;
}

// Whether `path` holds exactly `bytes` already (a texture unchanged since the last export).
bool Holds(const fs::path& path, const std::string& bytes) {
  std::error_code error;
  if (fs::file_size(path, error) != bytes.size() || error) return false;
  std::ifstream in(path, std::ios::binary);
  std::string held(bytes.size(), '\0');
  return in.read(held.data(), static_cast<std::streamsize>(held.size())) && held == bytes;
}

// Every file to its temporary first; one sync of the file system (a sync per file costs a
// disk flush each: minutes for thousands of textures); then the renames, the main file
// (files[0]) last. Companions that hold their bytes already are left alone.
Result<std::vector<std::string>> WriteFiles(const fs::path& folder,
                                            const std::vector<ExportFile>& files) {
  std::vector<std::pair<std::string, fs::path>> staged;
  auto discard = [&] {
    for (const auto& [temporary, target] : staged) unlink(temporary.c_str());
  };
  for (std::size_t i = files.size(); i-- > 0;) {
    const fs::path target = folder / files[i].name;
    if (i > 0 && Holds(target, files[i].bytes)) continue;
    auto temporary = WriteTemporary(target, files[i].bytes);
    if (!temporary.ok()) {
      discard();
      return ErrorMessage{temporary.error()};
    }
    staged.emplace_back(*temporary, target);
  }
  const int folder_fd = open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (folder_fd >= 0) {
    syncfs(folder_fd);
    close(folder_fd);
  }
  std::vector<std::string> written;
  written.reserve(files.size());
  for (std::size_t i = 0; i < staged.size(); ++i) {
    const auto& [temporary, target] = staged[i];
    if (rename(temporary.c_str(), target.c_str()) != 0) {
      const std::string why = std::generic_category().message(errno);
      for (std::size_t j = i; j < staged.size(); ++j) unlink(staged[j].first.c_str());
      return ErrorMessage{"cannot write " + target.string() + ": " + why};
    }
  }
  for (const auto& file : files) written.push_back((folder / file.name).string());
  return written;
}

// Removes the textures of models no longer exported from FOLDER/STEM_textures/ (a removed
// box's PNG), so the folder holds what the files name. Only files the exports name
// (model_*.png) are touched.
void PruneTextures(const fs::path& folder, const std::string& stem,
                   const std::vector<ExportFile>& files) {
  const fs::path textures = folder / (stem + "_textures");
  std::error_code error;
  if (!fs::is_directory(textures, error)) return;
  std::vector<fs::path> stale;
  const std::string prefix = stem + "_textures/";
  for (const auto& entry : fs::directory_iterator(textures, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("model_", 0) != 0 || entry.path().extension() != ".png") continue;
    const std::string relative = prefix + name;
    bool named = false;
    for (const auto& f : files) named = named || f.name == relative;
    if (!named) stale.push_back(entry.path());
  }
  for (const auto& path : stale) fs::remove(path, error);
}

}  // namespace

Result<std::vector<ExportFile>> RenderExport(const std::vector<StoredModel>& models,
                                             ExportFormat format, const ExportOptions& options,
                                             const std::string& main_name) {
  auto solids = exporting::MakeSolids(models, options);
  if (!solids.ok()) return ErrorMessage{solids.error()};
  return exporting::Render(*solids, format, options, main_name);
}

Result<std::vector<std::string>> WriteExport(const std::vector<StoredModel>& models,
                                             ExportFormat format, const ExportOptions& options,
                                             const std::string& out) {
  const fs::path path(out);
  if (path.filename().empty()) return ErrorMessage{"'" + out + "' names no file"};
  std::error_code error;
  if (fs::is_directory(path, error)) {
    return ErrorMessage{out + " is a folder: give a file name (or --all FOLDER)"};
  }
  auto files = RenderExport(models, format, options, path.filename().string());
  if (!files.ok()) return ErrorMessage{files.error()};
  const fs::path folder = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  auto written = WriteFiles(folder, *files);
  if (written.ok() && (format == ExportFormat::kUrdf || format == ExportFormat::kObj)) {
    PruneTextures(folder, path.stem().string(), *files);
  }
  return written;
}

Result<AllExportsReport> WriteAllExports(const std::vector<StoredModel>& models,
                                         const ExportOptions& options, const std::string& folder) {
  auto solids = exporting::MakeSolids(models, options);
  if (!solids.ok()) return ErrorMessage{solids.error()};
  AllExportsReport report;
  for (ExportFormat format : AllExportFormats()) {
    const std::string name = std::string("models") + ExportExtension(format);
    auto files = exporting::Render(*solids, format, options, name);
    if (!files.ok()) {
      // An old file of this format would no longer match the others: it goes.
      std::error_code ignored;
      if (fs::remove(fs::path(folder) / name, ignored)) {
        report.skipped.push_back(name + " removed: " + files.error());
      } else {
        report.skipped.push_back(files.error());
      }
      continue;
    }
    auto written = WriteFiles(folder, *files);
    if (!written.ok()) return ErrorMessage{written.error()};
    report.written.push_back(written->front());
    if (format == ExportFormat::kUrdf) PruneTextures(folder, "models", *files);
  }
  return report;
}

// ---- igms locate --json ----------------------------------------------------------------------

namespace {

using google::protobuf::Struct;
using google::protobuf::Value;

const Value* Field(const Struct& s, const std::string& name) {
  const auto it = s.fields().find(name);
  return it == s.fields().end() ? nullptr : &it->second;
}

std::optional<double> Number(const Struct& s, const std::string& name) {
  const Value* v = Field(s, name);
  if (!v || v->kind_case() != Value::kNumberValue) return std::nullopt;
  return v->number_value();
}

std::optional<object::Vec3> Vector(const Struct& s, const std::string& name) {
  const Value* v = Field(s, name);
  if (!v || v->kind_case() != Value::kListValue || v->list_value().values_size() != 3) {
    return std::nullopt;
  }
  object::Vec3 out;
  double xyz[3];
  for (int i = 0; i < 3; ++i) {
    const Value& e = v->list_value().values(i);
    if (e.kind_case() != Value::kNumberValue) return std::nullopt;
    xyz[i] = e.number_value();
  }
  out.set_x(xyz[0]);
  out.set_y(xyz[1]);
  out.set_z(xyz[2]);
  return out;
}

const Struct* Object(const Struct& s, const std::string& name) {
  const Value* v = Field(s, name);
  return v && v->kind_case() == Value::kStructValue ? &v->struct_value() : nullptr;
}

}  // namespace

Result<std::vector<StoredModel>> ReadLocateJson(const std::string& text) {
  std::vector<StoredModel> models;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = "line " + std::to_string(number) + ": ";
    Struct json;
    const auto status = google::protobuf::util::JsonStringToMessage(line, &json);
    if (!status.ok()) {
      return ErrorMessage{where + "not a JSON object (" + std::string(status.message()) + ")"};
    }
    const Value* found = Field(json, "found");
    if (!found || found->kind_case() != Value::kBoolValue) {
      return ErrorMessage{where + "no \"found\": not a line of igms locate --json"};
    }
    if (!found->bool_value()) continue;
    const Value* type = Field(json, "type");
    const std::string type_name =
        type && type->kind_case() == Value::kStringValue ? type->string_value() : "";
    const Struct* sigma = Object(json, "sigma");
    auto missing = [&](const std::string& field) {
      std::string message = where;
      message.append("the ")
          .append(type_name)
          .append(" has no valid \"")
          .append(field)
          .append("\"");
      return ErrorMessage{std::move(message)};
    };
    StoredModel m;
    m.id = static_cast<std::int64_t>(models.size()) + 1;
    if (type_name == "cylinder") {
      m.record.type = object::OBJECT_TYPE_CYLINDER;
      auto& c = m.record.cylinder;
      const auto center = Vector(json, "center");
      const auto axis = Vector(json, "axis");
      const auto radius = Number(json, "radius");
      const auto height = Number(json, "height");
      if (!center) return missing("center");
      if (!axis) return missing("axis");
      if (!radius) return missing("radius");
      if (!height) return missing("height");
      *c.mutable_center() = *center;
      *c.mutable_axis() = *axis;
      c.set_radius(*radius);
      c.set_height(*height);
      if (sigma) {
        if (auto v = Vector(*sigma, "center")) *c.mutable_center_sigma() = *v;
        c.set_radius_sigma(Number(*sigma, "radius").value_or(0));
        c.set_height_sigma(Number(*sigma, "height").value_or(0));
      }
    } else if (type_name == "box") {
      m.record.type = object::OBJECT_TYPE_BOX;
      auto& b = m.record.box;
      const auto center = Vector(json, "center");
      const auto size = Vector(json, "size");
      if (!center) return missing("center");
      if (!size) return missing("size");
      *b.mutable_center() = *center;
      *b.mutable_size() = *size;
      b.set_yaw_deg(Number(json, "yaw_deg").value_or(0));
      if (sigma) {
        if (auto v = Vector(*sigma, "center")) *b.mutable_center_sigma() = *v;
        if (auto v = Vector(*sigma, "size")) *b.mutable_size_sigma() = *v;
        b.set_yaw_sigma_deg(Number(*sigma, "yaw_deg").value_or(0));
      }
    } else {
      std::string message = where;
      message.append("type '").append(type_name).append("' is neither cylinder nor box");
      return ErrorMessage{std::move(message)};
    }
    if (auto problem = CheckExportModel(m)) return ErrorMessage{where + *problem};
    models.push_back(std::move(m));
  }
  return models;
}

}  // namespace igms::control
