// igms-export (`igms export`): the geometric database, or `igms locate --json` lines, in the
// formats robots and CAD tools load (docs/exports.md).
//
//   igms export --database FILE --format urdf --out site.urdf
//   igms export --database FILE --all exports/ --watch
//   igms locate ... --json | igms export --locate-json - --format stl --out part.stl
#include <signal.h>

#include <atomic>
#include <boost/program_options.hpp>
#include <chrono>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include "common/config/exit_codes.h"
#include "common/config/lab_config.h"
#include "common/version/version.h"
#include "control/database/database_path.h"
#include "control/export/export.h"

namespace po = boost::program_options;
using namespace igms::control;

namespace {

std::atomic<bool> g_stop{false};

void OnSignal(int) { g_stop = true; }

int Say(int code, const std::string& message) {
  std::cerr << "igms export: " << message << "\n";
  return code;
}

struct Source {
  std::unique_ptr<GeometricDatabase> database;  // or
  std::string locate_json;                      // the text of igms locate --json
};

struct Target {
  std::optional<ExportFormat> format;
  std::string out;
  std::string all;
};

// One export of the models now in the source. The exit status.
int ExportOnce(Source& source, const Target& target, const ExportOptions& options) {
  std::vector<StoredModel> models;
  if (source.database) {
    auto listed = source.database->ListModels();
    if (!listed.ok()) return Say(igms::kExitUnavailable, listed.error());
    models = std::move(*listed);
  } else {
    auto read = ReadLocateJson(source.locate_json);
    if (!read.ok()) return Say(igms::kExitUsage, "--locate-json: " + read.error());
    models = std::move(*read);
  }
  for (const auto& m : models) {
    if (auto problem = CheckExportModel(m)) {
      return Say(igms::kExitFailure, *problem + ": refused, nothing written");
    }
  }
  if (!target.all.empty()) {
    auto report = WriteAllExports(models, options, target.all);
    if (!report.ok()) return Say(igms::kExitUnavailable, report.error());
    for (const auto& skipped : report->skipped) Say(igms::kExitOk, skipped);
    std::cerr << "igms export: " << models.size() << " models in " << report->written.size()
              << " formats to " << target.all << "\n";
    return igms::kExitOk;
  }
  if (models.empty() && *target.format == ExportFormat::kStl) {
    return Say(igms::kExitFailure, "no models: STL has no empty form, so no STL was written");
  }
  auto written = WriteExport(models, *target.format, options, target.out);
  if (!written.ok()) return Say(igms::kExitUnavailable, written.error());
  std::cerr << "igms export: " << models.size() << " models to " << written->front() << "\n";
  return igms::kExitOk;
}

int Run(int argc, char** argv) {
  po::options_description desc(
      "igms export: the geometric database in the formats robots and CAD tools load\n"
      "Usage: igms export [--database FILE | --config LAB | --locate-json FILE]\n"
      "                   (--format FORMAT --out PATH | --all FOLDER) [--watch] [options]\n"
      "Options");
  std::string database, config, locate_json, format, out, all, base, units = "in", out_units = "m";
  ExportOptions options;
  int interval_ms = 250;
  desc.add_options()("help,h", "this help")("version", "print the version and exit")(
      "database", po::value(&database),
      "the geometric database to read (read only; default: lab.database of --config, else the "
      "operator's data folder)")("config", po::value(&config),
                                 "the lab file whose lab.database to read")(
      "locate-json", po::value(&locate_json),
      "read the JSON lines of `igms locate --json` from FILE ('-': standard input) instead")(
      "format", po::value(&format), "scene, urdf, gltf, glb, obj, stl or json")(
      "out", po::value(&out), "the file to write (with --format)")(
      "all", po::value(&all), "write every format into FOLDER as models.<format>")(
      "watch", po::bool_switch(), "stay, and export again whenever the database changes")(
      "interval-ms", po::value(&interval_ms)->default_value(250),
      "with --watch: how often to look for a change")(
      "base-from-world", po::value(&base),
      "x,y,z,roll,pitch,yaw: the site's frame in the robot's base frame (lengths in the output "
      "units, angles in radians, URDF's rpy)")(
      "frame", po::value(&options.frame)->default_value("world"), "the output frame's name")(
      "units", po::value(&units)->default_value("in"),
      "the calibration's world units: in, ft, m, cm, mm")("out-units",
                                                          po::value(&out_units)->default_value("m"),
                                                          "the files' units: m, cm, mm, in, ft")(
      "padding-sigmas", po::value(&options.padding_sigmas)->default_value(0),
      "move every surface out by K standard deviations of its position")(
      "name", po::value(&options.name)->default_value("igms_models"),
      "the scene's, robot's or asset's name");
  po::variables_map vm;
  try {
    po::store(po::parse_command_line(argc, argv, desc), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    std::cerr << "igms export: " << e.what() << " (igms export --help)\n";
    return igms::kExitUsage;
  }
  if (vm.count("help")) {
    std::cout << desc << "\n";
    return igms::kExitOk;
  }
  if (vm.count("version")) {
    std::cout << igms::version::Line("igms-export") << "\n";
    return igms::kExitOk;
  }
  const bool watch = vm["watch"].as<bool>();

  Target target;
  target.out = out;
  target.all = all;
  if (all.empty() == format.empty()) {
    return Say(igms::kExitUsage, "give --format FORMAT with --out PATH, or --all FOLDER");
  }
  if (!format.empty()) {
    target.format = ParseExportFormat(format);
    if (!target.format) {
      return Say(igms::kExitUsage,
                 "unknown format '" + format + "': scene, urdf, gltf, glb, obj, stl or json");
    }
    if (out.empty()) return Say(igms::kExitUsage, "--format needs --out PATH");
  }
  const auto world_unit = ParseLengthUnit(units);
  const auto out_unit = ParseLengthUnit(out_units);
  if (!world_unit) return Say(igms::kExitUsage, "unknown unit '" + units + "'");
  if (!out_unit) return Say(igms::kExitUsage, "unknown unit '" + out_units + "'");
  options.world_units = *world_unit;
  options.out_units = *out_unit;
  if (!base.empty()) {
    auto transform = ParseBaseTransform(base);
    if (!transform.ok()) return Say(igms::kExitUsage, "--base-from-world: " + transform.error());
    options.base_from_world = *transform;
  }
  if (!std::isfinite(options.padding_sigmas) || options.padding_sigmas < 0) {
    return Say(igms::kExitUsage, "--padding-sigmas must be 0 or more");
  }
  if (options.frame.empty() || options.frame.find_first_of(" \t\n\"<>&") != std::string::npos) {
    return Say(igms::kExitUsage, "--frame must be a name without spaces, quotes or <>&");
  }
  if (options.name.find_first_of("\n\"<>&") != std::string::npos) {
    return Say(igms::kExitUsage, "--name must be one line without quotes or <>&");
  }
  if (interval_ms < 10) return Say(igms::kExitUsage, "--interval-ms must be 10 or more");

  Source source;
  if (!locate_json.empty()) {
    if (!database.empty() || !config.empty()) {
      return Say(igms::kExitUsage, "--locate-json replaces --database and --config");
    }
    if (watch) return Say(igms::kExitUsage, "--watch watches a database, not --locate-json");
    std::stringstream text;
    if (locate_json == "-") {
      text << std::cin.rdbuf();
    } else {
      std::ifstream in(locate_json);
      if (!in) return Say(igms::kExitUnavailable, "cannot read " + locate_json);
      text << in.rdbuf();
    }
    source.locate_json = text.str();
  } else {
    igms::config::LabConfig lab;
    if (!config.empty()) {
      try {
        lab = igms::config::LabConfig::Load(config);
      } catch (const igms::config::ConfigError& e) {
        return Say(igms::kExitUsage, e.what());
      }
    }
    auto path = ResolveDatabasePath(lab, database, UserFolders::FromEnvironment());
    if (!path.ok()) return Say(igms::kExitUsage, path.error());
    auto opened = GeometricDatabase::OpenReadOnly(*path);
    if (!opened.ok()) return Say(igms::kExitUnavailable, opened.error());
    source.database = std::move(*opened);
  }

  if (!watch) return ExportOnce(source, target, options);

  struct sigaction action {};
  action.sa_handler = OnSignal;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  // PRAGMA data_version moves when another connection commits: export again then. A failed
  // export while watching is reported and tried again at the next change.
  auto version = source.database->DataVersion();
  if (!version.ok()) return Say(igms::kExitUnavailable, version.error());
  int status = ExportOnce(source, target, options);
  if (status == igms::kExitUsage || status == igms::kExitUnavailable) return status;
  std::cerr << "igms export: watching " << source.database->path() << "\n";
  while (!g_stop) {
    std::this_thread::sleep_for(std::chrono::milliseconds(interval_ms));
    auto now = source.database->DataVersion();
    if (!now.ok()) return Say(igms::kExitUnavailable, now.error());
    if (*now == *version) continue;
    version = *now;
    ExportOnce(source, target, options);
  }
  return igms::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    return Say(igms::kExitUnavailable, std::string("unexpected error: ") + e.what());
  }
}
