// igms-truth-table: a modelling session's database against the simulated site's truth, as
// the table igms-vision-demo prints. Each cylinder and box of the scene is matched with the
// nearest present model of its type (each model used once).
//
//   igms-truth-table --config lab.yaml --database FILE [--json FILE] [--require-all]
// Exit: 0; 1 with --require-all when an object has no model; 2 bad input.
#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <set>

#include "common/config/exit_codes.h"
#include "common/config/process_options.h"
#include "common/sim/capture/sim_capture.h"
#include "common/sim/vision/truth_table.h"
#include "control/database/geometric_database.h"

namespace po = boost::program_options;

namespace {

Eigen::Vector3d CenterOf(const igms::control::StoredModel& m) {
  const auto& c = m.record.type == igms::object::OBJECT_TYPE_BOX ? m.record.box.center()
                                                                 : m.record.cylinder.center();
  return {c.x(), c.y(), c.z()};
}

}  // namespace

int main(int argc, char** argv) {
  try {
    po::options_description extra("Table options");
    extra.add_options()("video", po::value<std::string>()->default_value("video"),
                        "the video server's process name: its scene is the truth")(
        "database", po::value<std::string>(), "the session's geometric database (required)")(
        "json", po::value<std::string>(), "also write the table as JSON here")(
        "require-all", po::bool_switch(), "exit 1 when an object has no model")(
        "objects", po::value<std::vector<std::string>>()->multitoken(),
        "only these objects (by name): those the session modelled");
    int exit_code = 0;
    auto process = igms::config::ParseProcessOptions(
        argc, argv, "truth-table", "igms-truth-table: a session's models against the truth", extra,
        igms::config::Keys(), &exit_code);
    if (!process) return exit_code;
    if (!process->flags.count("database")) {
      std::cerr << "igms-truth-table: --database FILE is required\n";
      return igms::kExitUsage;
    }
    igms::config::ProcessOptions video = *process;
    video.name = process->flags["video"].as<std::string>();
    const auto sim = igms::video::ConfiguredSimScene(video);
    if (!sim.scene) {
      std::cerr << "igms-truth-table: " << sim.error << "\n";
      return igms::kExitUsage;
    }
    const std::string path = process->flags["database"].as<std::string>();
    auto database = igms::control::GeometricDatabase::Open(path, {"igms-truth-table", ""});
    if (!database.ok()) {
      std::cerr << "igms-truth-table: " << path << ": " << database.error() << "\n";
      return igms::kExitUsage;
    }
    auto models = (*database)->ListModels();
    if (!models.ok()) {
      std::cerr << "igms-truth-table: " << models.error() << "\n";
      return igms::kExitFailure;
    }
    const igms::site::Scene& scene = *sim.scene;
    std::vector<igms::site::TruthRow> rows;
    std::set<int64_t> used;
    int missing = 0;
    for (size_t i = 0; i < scene.objects.size(); ++i) {
      igms::site::TruthRow row;
      row.name = igms::site::ObjectName(scene, i);
      igms::object::LocateRequest request;
      if (!igms::site::Truth(scene.objects[i].shape, &row, &request)) continue;
      if (process->flags.count("objects")) {
        const auto& only = process->flags["objects"].as<std::vector<std::string>>();
        if (std::find(only.begin(), only.end(), row.name) == only.end()) continue;
      }
      const igms::control::StoredModel* best = nullptr;
      for (const auto& m : *models) {
        if (m.record.type != request.type() || used.count(m.id)) continue;
        if (!best ||
            (CenterOf(m) - row.true_center).norm() < (CenterOf(*best) - row.true_center).norm()) {
          best = &m;
        }
      }
      igms::object::LocateResponse got;
      if (best) {
        used.insert(best->id);
        got.set_found(true);
        *got.mutable_cylinder() = best->record.cylinder;
        *got.mutable_box() = best->record.box;
        got.set_locate_ms(best->record.provenance.locate_ms);
        got.set_fetch_ms(best->record.provenance.fetch_ms);
      } else {
        got.set_detail("no model of this type in the database");
        missing++;
      }
      igms::site::Compare(scene.objects[i].shape, got, &row);
      if (best) row.round_trip_ms = best->record.provenance.round_trip_ms;
      rows.push_back(row);
    }
    std::cout << igms::site::TruthTable(rows);
    for (const auto& m : *models) {
      if (!used.count(m.id)) std::cout << fmt::format("model {} matches no object\n", m.id);
    }
    std::cout << fmt::format("{} objects, {} modelled; database {}\n", rows.size(),
                             rows.size() - missing, path);
    if (process->flags.count("json")) {
      std::ofstream json(process->flags["json"].as<std::string>());
      json << igms::site::TruthJson(rows, 0, sim.origin);
      if (!json) {
        std::cerr << "igms-truth-table: cannot write the JSON file\n";
        return igms::kExitFailure;
      }
    }
    return process->flags["require-all"].as<bool>() && missing > 0 ? igms::kExitFailure : 0;
  } catch (const std::exception& e) {
    std::cerr << "igms-truth-table: " << e.what() << "\n";
    return igms::kExitUsage;
  }
}
