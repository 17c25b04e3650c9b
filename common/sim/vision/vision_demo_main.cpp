// igms-vision-demo: the vision half of a modelling session against running servers. Asks the
// video server (sim backend) to grab, makes the operator's four marks for every cylinder and
// box of the simulated scene from its ground truth (common/sim/marks.h), sends each Locate
// to the object server over TCP as the control client does, and prints true against
// modelled pose and size with the errors and times. Writes table.txt and results.json into
// the --out folder. Starts no server. Exit: 0 all found, 1 a step failed (named on stderr),
// 2 bad arguments or configuration.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "common/base/json.h"
#include "common/config/process_options.h"
#include "common/net/client.h"
#include "common/sim/capture/sim_capture.h"
#include "common/sim/marks.h"
#include "common/sim/vision/truth_table.h"
#include "igms/object.pb.h"
#include "igms/video.pb.h"
#include "object_server/object_service.h"
#include "object_server/result_json.h"
#include "object_server/solid_models.h"
#include "video_server/video_config.h"

namespace po = boost::program_options;
using namespace std::chrono_literals;

namespace {

int Fail(const std::string& step, const std::string& message) {
  std::cerr << "igms-vision-demo: step '" << step << "' failed: " << message << "\n";
  return 1;
}

int Run(int argc, char** argv) {
  po::options_description extra("Vision demo options");
  extra.add_options()("video", po::value<std::string>()->default_value("video"),
                      "the video server's process name in the configuration")(
      "object", po::value<std::string>()->default_value("object"),
      "the object server's process name")("out", po::value<std::string>(),
                                          "folder for table.txt and results.json (created)")(
      "mark-seed", po::value<uint64_t>()->default_value(1), "seed of the generated marks");
  int exit_code = 0;
  auto process = igms::config::ParseProcessOptions(
      argc, argv, "vision-demo",
      "igms-vision-demo: grab, mark every simulated object, locate each over TCP, compare with "
      "the ground truth",
      extra, igms::config::Keys(), &exit_code);
  if (!process) return exit_code;
  const std::string video_name = process->flags["video"].as<std::string>();
  const std::string object_name = process->flags["object"].as<std::string>();
  const uint64_t mark_seed = process->flags["mark-seed"].as<uint64_t>();
  std::string out = process->flags.count("out") ? process->flags["out"].as<std::string>() : "";
  if (out.empty()) {
    out = fmt::format("vision-demo-{}", std::chrono::duration_cast<std::chrono::seconds>(
                                            std::chrono::system_clock::now().time_since_epoch())
                                            .count());
  }

  // The ground truth: the scene the video server's configuration names, as it renders it.
  igms::config::ProcessOptions video_process = *process;
  video_process.name = video_name;
  if (igms::video::ReadVideoConfig(video_process).backend != "sim") {
    std::cerr << "igms-vision-demo: processes." << video_name
              << ".backend must be sim: the demo compares with the simulated site's truth\n";
    return 2;
  }
  igms::video::SimSceneChoice sim = igms::video::ConfiguredSimScene(video_process);
  if (!sim.scene) return Fail("scene", sim.error);
  const igms::site::Scene& scene = *sim.scene;
  if (process->check_only) return igms::config::CheckPassed(*process);

  boost::asio::io_context io;
  auto work = boost::asio::make_work_guard(io);
  std::thread io_thread([&] { io.run(); });
  auto client_for = [&](const std::string& name) {
    igms::net::ClientOptions options;
    options.name = "vision-demo";
    options.host = process->HostOf(name);
    options.port = process->PortOf(name);
    options.token = process->lab.token;
    options.max_frame_bytes = 64u << 20;
    auto client = std::make_unique<igms::net::Client>(io, options);
    client->Start();
    return client;
  };
  auto video = client_for(video_name);
  auto object = client_for(object_name);
  auto stop = [&] {
    video->Stop();
    object->Stop();
    work.reset();
    io.stop();
    io_thread.join();
  };

  // A missing server is named at once rather than after a call's full timeout.
  for (const auto& [name, client] :
       {std::pair{video_name, video.get()}, std::pair{object_name, object.get()}}) {
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (!client->connected() && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(20ms);
    }
    if (!client->connected()) {
      const std::string where = fmt::format("{}:{}", process->HostOf(name), process->PortOf(name));
      stop();
      return Fail("connect " + name, "nothing answers at " + where + " within 5 s");
    }
  }
  auto grab = video->CallSync<igms::video::GrabResponse>("igms.video.VideoService.Grab",
                                                         igms::video::GrabRequest{}, 60s);
  if (!grab.ok()) {
    stop();
    return Fail("grab", fmt::format("{}:{}: {}", process->HostOf(video_name),
                                    process->PortOf(video_name), grab.status.message));
  }
  const uint64_t frame_id = grab.value.frame_id();
  std::cout << fmt::format("grabbed frame {} ({}x{}) from {} in {:.0f} ms; scene: {}\n", frame_id,
                           grab.value.width(), grab.value.height(), video_name,
                           grab.value.capture_ms(), sim.origin);

  std::vector<igms::site::TruthRow> rows;
  std::string failed;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const auto& object_i = scene.objects[i];
    igms::site::TruthRow row;
    row.name = igms::site::ObjectName(scene, i);
    igms::object::LocateRequest request;
    if (!igms::site::Truth(object_i.shape, &row, &request)) continue;
    const auto marks =
        igms::site::GenerateMarks(object_i.shape, scene.cameras.left, mark_seed * 1000 + i);
    if (!marks) {
      stop();
      return Fail("marks " + row.name, "the object is not wholly in front of the left camera");
    }
    igms::object::MarksToProto(*marks, &request);
    request.set_frame_id(frame_id);
    const auto start = std::chrono::steady_clock::now();
    auto got = object->CallSync<igms::object::LocateResponse>("igms.object.ObjectService.Locate",
                                                              request, 60s);
    row.round_trip_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!got.ok()) {
      stop();
      return Fail("locate " + row.name,
                  fmt::format("{}:{}: {}", process->HostOf(object_name),
                              process->PortOf(object_name), got.status.message));
    }
    igms::site::Compare(object_i.shape, got.value, &row);
    if (!row.found && failed.empty()) failed = "locate " + row.name;
    rows.push_back(row);
  }
  stop();

  const std::string table = igms::site::TruthTable(rows);
  std::cout << table;
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  std::ofstream(out + "/table.txt") << table;
  std::ofstream json(out + "/results.json");
  json << igms::site::TruthJson(rows, frame_id, sim.origin);
  if (!json) return Fail("write results", "cannot write " + out + "/results.json");
  std::cout << "wrote " << out << "/table.txt and " << out << "/results.json\n";
  if (rows.empty()) return Fail("scene", "the scene has no cylinder or box to locate");
  if (!failed.empty()) return Fail(failed, "not found (see the table)");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "igms-vision-demo: " << e.what() << "\n";
    return 1;
  }
}
