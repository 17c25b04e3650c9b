// The walls of docs/architecture.md's layer table, checked on the includes of every source
// file of the project (tests and benchmarks aside): a file includes headers of its own
// component and of the layers its layer stands on, nothing else. A breach fails naming the
// file, the line and the rule; a folder the table does not know fails too, so the table
// grows with the tree.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <string>
#include <vector>

namespace igms::architecture {
namespace {

// docs/architecture.md's layers, lowest first.
enum class Layer {
  kMessages,
  kFoundation,
  kCalibration,
  kWire,
  kComponents,
  kSimulation,
  kOperator,
  kTools,
  kTestsAndBenchmarks,
};

const char* LayerName(Layer layer) {
  static const char* const kNames[] = {"messages", "foundation", "calibration",
                                       "wire",     "components", "simulation",
                                       "operator", "tools",      "tests and benchmarks"};
  return kNames[static_cast<int>(layer)];
}

// Whether a layer may include another layer's headers (its own component's are always fine).
bool StandsOn(Layer from, Layer to) {
  using L = Layer;
  switch (from) {
    case L::kMessages:
      return false;
    case L::kFoundation:
    case L::kCalibration:
    case L::kWire:
      return to == L::kMessages || to == L::kFoundation;
    case L::kComponents:
    case L::kOperator:
      return to == L::kMessages || to == L::kFoundation || to == L::kCalibration || to == L::kWire;
    case L::kSimulation:
      return to != L::kOperator && to != L::kTools && to != L::kTestsAndBenchmarks;
    case L::kTools:
      return to != L::kOperator && to != L::kTestsAndBenchmarks;
    case L::kTestsAndBenchmarks:
      return true;
  }
  return false;
}

struct Component {
  std::string name;  // the folder, e.g. "video_server", "device_daemons/ranger"
  Layer layer;
};

bool Under(const std::string& path, const std::string& folder) {
  return path == folder || path.rfind(folder + "/", 0) == 0;
}

// The component a path (a source file or an included header, from the repository root)
// belongs to; nullopt for a folder the layer table does not name.
std::optional<Component> ComponentOf(const std::string& path) {
  struct Area {
    const char* folder;
    Layer layer;
  };
  // Longest match first: common/calibration/cli is a tool over common/calibration.
  static const Area kAreas[] = {
      {"common/calibration/cli", Layer::kTools},
      {"common/tools", Layer::kTools},
      {"common/sim", Layer::kSimulation},
      {"common/calibration", Layer::kCalibration},
      {"common/wire", Layer::kWire},
      {"common/base", Layer::kFoundation},
      {"common/stats", Layer::kFoundation},
      {"common/version", Layer::kFoundation},
      {"common/log", Layer::kFoundation},
      {"common/config", Layer::kFoundation},
      {"common/net", Layer::kFoundation},
      {"common/certs", Layer::kFoundation},
      {"common/process", Layer::kFoundation},
      {"common/geometry", Layer::kFoundation},
      {"igms", Layer::kMessages},  // generated from proto/igms/*.proto
      {"proto", Layer::kMessages},
      {"video_server", Layer::kComponents},
      {"object_server", Layer::kComponents},
      {"sound_server", Layer::kComponents},
      {"control", Layer::kOperator},
      {"tests", Layer::kTestsAndBenchmarks},
      {"bench", Layer::kTestsAndBenchmarks},
  };
  // Every device daemon is a component of its own; device_daemons/serial is their shared base.
  static const std::regex kDaemon("^(device_daemons/[^/]+)/.*");
  std::smatch m;
  if (std::regex_match(path, m, kDaemon)) return Component{m[1], Layer::kComponents};
  for (const Area& area : kAreas) {
    if (Under(path, area.folder)) return Component{area.folder, area.layer};
  }
  return std::nullopt;
}

bool IsProgramMain(const std::string& file) {
  const std::string name = std::filesystem::path(file).filename().string();
  return name == "main.cpp" || (name.size() > 9 && name.ends_with("_main.cpp"));
}

// Why `file` may not include `header` (both from the repository root); empty when it may.
std::string CheckInclude(const std::string& file, const std::string& header) {
  const auto from = ComponentOf(file);
  if (!from) {
    return file +
           " is in no layer of docs/architecture.md: add its folder to the table and "
           "to this test";
  }
  const auto to = ComponentOf(header);
  if (!to) {
    return "includes " + header + ", which is in no layer of docs/architecture.md";
  }
  if (from->name == to->name) return "";
  // The device daemons share their serial base.
  if (from->layer == Layer::kComponents && to->name == "device_daemons/serial" &&
      Under(from->name, "device_daemons")) {
    return "";
  }
  // A component's program (not its library) registers the simulation's run-time backends.
  if (from->layer == Layer::kComponents && IsProgramMain(file) &&
      (Under(header, "common/sim/capture") || Under(header, "common/sim/ranger"))) {
    return "";
  }
  // The simulated operator's table reads what a session stored: the operator's database, and
  // nothing else of the operator, so the control client never needs the truth.
  if (Under(file, "common/sim/session") && IsProgramMain(file) &&
      Under(header, "control/database")) {
    return "";
  }
  if (from->layer == Layer::kComponents && to->layer == Layer::kComponents) {
    return "includes " + header + ": a component (" + from->name +
           ") may not include another component's headers (" + to->name +
           "); shared code goes below both (common/wire, common/calibration)";
  }
  if (!StandsOn(from->layer, to->layer)) {
    return "includes " + header + ": " + LayerName(from->layer) + " (" + from->name +
           ") may not include " + LayerName(to->layer) + " (" + to->name + ")";
  }
  return "";
}

TEST(IncludeLayers, RulesRefuseWhatTheTableForbids) {
  // Allowed.
  EXPECT_EQ(CheckInclude("object_server/object_service.cpp", "common/wire/image_message.h"), "");
  EXPECT_EQ(CheckInclude("video_server/main.cpp", "common/sim/capture/sim_capture.h"), "");
  EXPECT_EQ(CheckInclude("device_daemons/ranger/main.cpp", "common/sim/ranger/site_ranger.h"), "");
  EXPECT_EQ(CheckInclude("common/sim/capture/sim_capture.h", "video_server/capture_backend.h"), "");
  EXPECT_EQ(CheckInclude("common/sim/session/truth_table_main.cpp",
                         "control/database/geometric_database.h"),
            "");
  EXPECT_EQ(
      CheckInclude("device_daemons/ranger/ranger_daemon.h", "device_daemons/serial/daemon_base.h"),
      "");
  EXPECT_EQ(CheckInclude("common/calibration/cli/commands.cpp", "common/sim/synthetic_platform.h"),
            "");
  EXPECT_EQ(CheckInclude("common/net/server.h", "igms/common.pb.h"), "");
  // Refused.
  EXPECT_NE(CheckInclude("object_server/object_service.cpp", "video_server/proto_convert.h")
                .find("another component"),
            std::string::npos);
  EXPECT_NE(CheckInclude("video_server/video_config.cpp", "common/sim/capture/sim_capture.h")
                .find("components (video_server) may not include simulation (common/sim)"),
            std::string::npos);
  EXPECT_NE(CheckInclude("video_server/main.cpp", "common/sim/renderer.h"), "");
  EXPECT_NE(CheckInclude("device_daemons/ranger/ranger_site.cpp", "common/sim/range.h"), "");
  EXPECT_NE(
      CheckInclude("device_daemons/ranger/ranger_sim.h", "device_daemons/viewer/viewer_sim.h"), "");
  EXPECT_NE(CheckInclude("common/calibration/dlt.cpp", "common/sim/testbed.h"), "");
  EXPECT_NE(CheckInclude("common/geometry/camera.cpp", "common/calibration/calibration_file.h"),
            "");
  EXPECT_NE(CheckInclude("common/wire/image_message.h", "video_server/edges.h"), "");
  EXPECT_NE(CheckInclude("video_server/edges.cpp", "tests/support/child_process.h"), "");
  EXPECT_NE(CheckInclude("common/newthing/a.cpp", "common/log/log.h").find("no layer"),
            std::string::npos);
}

// Every folder of the project that holds sources, tests and benchmarks aside.
const char* const kSourceRoots[] = {"common",        "proto",        "video_server",
                                    "object_server", "sound_server", "device_daemons",
                                    "control"};

TEST(IncludeLayers, EverySourceFileKeepsToItsLayer) {
  const char* dir = std::getenv("IGMS_SOURCE_DIR");
  ASSERT_NE(dir, nullptr) << "IGMS_SOURCE_DIR names the repository (set by CTest)";
  const std::filesystem::path root(dir);
  static const std::regex kInclude(R"(^\s*#\s*include\s*"([^"]+)\")");
  int files = 0, includes = 0;
  for (const char* top : kSourceRoots) {
    if (!std::filesystem::exists(root / top)) continue;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(root / top)) {
      const std::string ext = entry.path().extension().string();
      if (!entry.is_regular_file() || (ext != ".h" && ext != ".cpp" && ext != ".cc")) continue;
      const std::string file = std::filesystem::relative(entry.path(), root).generic_string();
      ++files;
      std::ifstream in(entry.path());
      std::string line;
      for (int number = 1; std::getline(in, line); ++number) {
        std::smatch m;
        if (!std::regex_search(line, m, kInclude)) continue;
        ++includes;
        std::string header = m[1];
        // A bare name is a header beside the file.
        if (header.find('/') == std::string::npos) {
          header = (std::filesystem::path(file).parent_path() / header).generic_string();
        }
        const std::string why = CheckInclude(file, header);
        if (!why.empty()) ADD_FAILURE() << file << ":" << number << ": " << why;
      }
    }
  }
  // The walk found the tree (a wrong root must not pass for a clean one).
  EXPECT_GT(files, 200);
  EXPECT_GT(includes, 300);
}

}  // namespace
}  // namespace igms::architecture
