// igms-plan: writes the script of a modelling session for the simulated site the lab's video
// server renders (plan.h): every cylinder and box looked at, marked and identified.
//
//   igms-plan --config lab.yaml [--out session.yaml] [--mark-seed N] [--no-pan] [--no-range]
//             [--objects NAME...]
#include <fstream>
#include <iostream>

#include "common/config/exit_codes.h"
#include "common/config/process_options.h"
#include "common/sim/capture/sim_capture.h"
#include "common/sim/session/plan.h"
#include "video_server/video_config.h"

namespace po = boost::program_options;

int main(int argc, char** argv) {
  try {
    po::options_description extra("Planner options");
    extra.add_options()("video", po::value<std::string>()->default_value("video"),
                        "the video server's process name: its scene is planned")(
        "out", po::value<std::string>(), "write the script here (default: standard output)")(
        "mark-seed", po::value<uint64_t>()->default_value(1), "seed of the operator's marks")(
        "no-pan", po::bool_switch(), "look straight ahead at every object")(
        "no-range", po::bool_switch(), "do not take ultrasonic ranges")(
        "objects", po::value<std::vector<std::string>>()->multitoken(),
        "plan only these objects (by name)");
    int exit_code = 0;
    auto process = igms::config::ParseProcessOptions(
        argc, argv, "plan", "igms-plan: the script of a session that models the simulated site",
        extra, igms::config::Keys(), &exit_code);
    if (!process) return exit_code;
    igms::config::ProcessOptions video = *process;
    video.name = process->flags["video"].as<std::string>();
    if (igms::video::ReadVideoConfig(video).backend != "sim") {
      std::cerr << "igms-plan: processes." << video.name
                << ".backend must be sim: only the simulated site has a truth to plan from\n";
      return igms::kExitUsage;
    }
    const auto sim = igms::video::ConfiguredSimScene(video);
    if (!sim.scene) {
      std::cerr << "igms-plan: " << sim.error << "\n";
      return igms::kExitUsage;
    }
    if (process->check_only) return igms::config::CheckPassed(*process);
    igms::site::PlanOptions options;
    options.mark_seed = process->flags["mark-seed"].as<uint64_t>();
    options.pan = !process->flags["no-pan"].as<bool>();
    options.range = !process->flags["no-range"].as<bool>();
    if (process->flags.count("objects")) {
      options.only = process->flags["objects"].as<std::vector<std::string>>();
    }
    auto plan = igms::site::PlanSession(*sim.scene, sim.platform, options);
    if (!plan.ok()) {
      std::cerr << "igms-plan: " << plan.error() << "\n";
      return igms::kExitFailure;
    }
    const std::string script = igms::site::PlanScript(*plan, sim.origin, options);
    if (!process->flags.count("out")) {
      std::cout << script;
      return 0;
    }
    const std::string out = process->flags["out"].as<std::string>();
    std::ofstream file(out);
    file << script;
    file.close();
    if (!file) {
      std::cerr << "igms-plan: cannot write " << out << "\n";
      return igms::kExitFailure;
    }
    std::cerr << "igms-plan: " << plan->size() << " objects planned into " << out << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "igms-plan: " << e.what() << "\n";
    return igms::kExitUsage;
  }
}
