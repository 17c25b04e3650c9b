// Marks to model, end to end: igms-video-server (simulated site, the default
// testbed scene, 512x480) and igms-object-server started here as real processes on loopback,
// a grab, then the operator's Locate requests over TCP for every object of the scene, as the
// control client sends them; a new grab every round, so each round's first request also
// pays the frame's fetch from the video server. Prints p50 and p99 of the round trip (and of
// the server's own locate and fetch times) beside the offline locate time of the same marks
// on the same scene in this process, the baseline of the same run. Targets: p50 under 10 ms,
// p99 under 30 ms.
//
// Usage: bench_object_latency [rounds=40] [bin_dir] [calibration]
// (defaults: the build's bin folder next to this program's, the thesis calibration).
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <opencv2/core/utility.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_main.h"
#include "common/calibration/calibration_file.h"
#include "common/net/client.h"
#include "common/sim/marks.h"
#include "common/sim/renderer.h"
#include "common/sim/testbed.h"
#include "common/sim/vision/evaluation.h"
#include "common/stats/percentile.h"
#include "igms/object.pb.h"
#include "igms/video.pb.h"
#include "object_server/locate.h"
#include "object_server/object_service.h"

extern char** environ;

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

// A server program on a free port, stopped with SIGTERM when destroyed.
class Server {
 public:
  Server(const std::string& program, std::vector<std::string> args, const std::string& port_file) {
    std::filesystem::remove(port_file);
    std::vector<std::string> argv = {program, "--port", "0", "--port-file", port_file};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<char*> raw;
    raw.reserve(argv.size() + 1);
    for (auto& a : argv) raw.push_back(a.data());
    raw.push_back(nullptr);
    if (posix_spawn(&pid_, raw[0], nullptr, nullptr, raw.data(), environ) != 0) pid_ = -1;
    for (int i = 0; i < 400 && pid_ > 0 && port_ == 0; ++i) {
      std::ifstream in(port_file);
      int port = 0;
      if (in >> port && port > 0)
        port_ = static_cast<uint16_t>(port);
      else
        std::this_thread::sleep_for(50ms);
    }
  }
  ~Server() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      int status = 0;
      waitpid(pid_, &status, 0);
    }
  }
  uint16_t port() const { return port_; }

 private:
  pid_t pid_ = -1;
  uint16_t port_ = 0;
};

std::unique_ptr<igms::net::Client> Connect(boost::asio::io_context& io, uint16_t port) {
  igms::net::ClientOptions options;
  options.port = port;
  options.name = "latency-bench";
  options.max_frame_bytes = 64u << 20;
  auto client = std::make_unique<igms::net::Client>(io, options);
  client->Start();
  for (int i = 0; i < 250 && !client->connected(); ++i) std::this_thread::sleep_for(20ms);
  return client;
}

// The operator's Locate request for one solid's marks on a grab.
igms::object::LocateRequest RequestFor(bool cylinder, const igms::site::Marks& marks,
                                       uint64_t frame_id) {
  igms::object::LocateRequest request;
  request.set_type(cylinder ? igms::object::OBJECT_TYPE_CYLINDER : igms::object::OBJECT_TYPE_BOX);
  igms::object::MarksToProto(marks, &request);
  request.set_frame_id(frame_id);
  return request;
}

void Row(const char* what, const std::vector<double>& v) {
  std::printf("%-44s %5zu %8.2f %8.2f %8.2f\n", what, v.size(), igms::stats::Percentile(v, 0.5),
              igms::stats::Percentile(v, 0.99),
              v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()));
}

// What the run measured, in ms, and its counts.
struct Figures {
  std::vector<double> rtt_all, rtt_first, rtt_cached, server_locate, server_fetch, offline,
      offline_cpu;
  std::vector<double> burst_all, burst_serial;
  size_t burst_size = 0;
  int found = 0, requests = 0, failures = 0;
};

// The video and object servers as processes, the object server fetching from the video one.
struct Servers {
  std::unique_ptr<Server> video, object;
};

std::optional<Servers> StartServers(const std::string& bin, const std::string& calibration,
                                    const std::string& scratch) {
  Servers servers;
  const std::vector<std::string> common = {"--set", "lab.calibration=" + calibration};
  std::vector<std::string> video_args = {"--name", "video", "--set", "processes.video.backend=sim"};
  video_args.insert(video_args.end(), common.begin(), common.end());
  servers.video =
      std::make_unique<Server>(bin + "/igms-video-server", video_args, scratch + "/video.port");
  if (!servers.video->port()) {
    std::fprintf(stderr, "bench_object_latency: %s/igms-video-server did not start\n", bin.c_str());
    return std::nullopt;
  }
  std::vector<std::string> object_args = {
      "--name", "object", "--set", "processes.video.port=" + std::to_string(servers.video->port())};
  object_args.insert(object_args.end(), common.begin(), common.end());
  servers.object =
      std::make_unique<Server>(bin + "/igms-object-server", object_args, scratch + "/object.port");
  if (!servers.object->port()) {
    std::fprintf(stderr, "bench_object_latency: %s/igms-object-server did not start\n",
                 bin.c_str());
    return std::nullopt;
  }
  return servers;
}

// The marks the operator puts on object i in `round` (its seed), and whether it is a
// cylinder; nothing for a solid the locator does not model or marks that cannot be drawn.
std::optional<igms::site::Marks> MarksFor(const igms::site::Scene& scene, size_t i, int round,
                                          bool* cylinder) {
  const auto& shape = scene.objects[i].shape;
  *cylinder = std::holds_alternative<igms::site::Cylinder>(shape);
  if (!*cylinder && !std::holds_alternative<igms::site::Box>(shape)) return std::nullopt;
  return igms::site::GenerateMarks(shape, scene.cameras.left,
                                   static_cast<size_t>(round) * 1000 + i);
}

// The same marks located offline in this process: wall and thread CPU time.
void LocateOffline(const igms::site::Scene& scene, const igms::site::StereoImages& images,
                   bool cylinder, const igms::site::Marks& marks, Figures& f) {
  igms::object::LocateInput in;
  in.type = cylinder ? igms::object::SolidType::kCylinder : igms::object::SolidType::kBox;
  in.marks = marks;
  in.left = images.left;
  in.right = images.right;
  in.left_camera = scene.cameras.left;
  in.right_camera = scene.cameras.right;
  timespec c0, c1;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c0);
  const auto t0 = Clock::now();
  (void)igms::object::Locate(in);
  f.offline.push_back(Ms(Clock::now() - t0));
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c1);
  f.offline_cpu.push_back(static_cast<double>(c1.tv_sec - c0.tv_sec) * 1e3 +
                          static_cast<double>(c1.tv_nsec - c0.tv_nsec) * 1e-6);
}

// `rounds` rounds of a grab and one Locate at a time for each object, each beside its
// offline locate. False when a grab fails.
bool SerialRounds(int rounds, igms::net::Client& video, igms::net::Client& object,
                  const igms::site::Scene& scene, const igms::site::StereoImages& images,
                  Figures& f) {
  for (int round = 0; round < rounds; ++round) {
    auto grab = video.CallSync<igms::video::GrabResponse>("igms.video.VideoService.Grab",
                                                          igms::video::GrabRequest{}, 60s);
    if (!grab.ok()) {
      std::fprintf(stderr, "bench_object_latency: grab failed: %s\n", grab.status.message.c_str());
      return false;
    }
    bool first = true;
    for (size_t i = 0; i < scene.objects.size(); ++i) {
      bool cylinder = false;
      const auto marks = MarksFor(scene, i, round, &cylinder);
      if (!marks) continue;
      const auto request = RequestFor(cylinder, *marks, grab.value.frame_id());
      const auto start = Clock::now();
      auto got = object.CallSync<igms::object::LocateResponse>("igms.object.ObjectService.Locate",
                                                               request, 60s);
      const double rtt = Ms(Clock::now() - start);
      ++f.requests;
      if (!got.ok()) {
        ++f.failures;
        continue;
      }
      f.found += got.value.found();
      if (!got.value.found())
        std::fprintf(stderr, "round %d, %s: not found: %s\n", round, scene.objects[i].name.c_str(),
                     got.value.detail().c_str());
      f.rtt_all.push_back(rtt);
      (first ? f.rtt_first : f.rtt_cached).push_back(rtt);
      first = false;
      f.server_locate.push_back(got.value.locate_ms());
      f.server_fetch.push_back(got.value.fetch_ms());
      LocateOffline(scene, images, cylinder, *marks, f);
    }
  }
  return true;
}

// A grab's objects asked for all at once (an operator queueing several models): time to
// the last answer, beside the same requests one at a time in the same round.
void BurstRounds(int rounds, igms::net::Client& video, igms::net::Client& object,
                 const igms::site::Scene& scene, Figures& f) {
  for (int round = 0; round < rounds; ++round) {
    auto grab = video.CallSync<igms::video::GrabResponse>("igms.video.VideoService.Grab",
                                                          igms::video::GrabRequest{}, 60s);
    if (!grab.ok()) break;
    std::vector<igms::object::LocateRequest> burst;
    for (size_t i = 0; i < scene.objects.size(); ++i) {
      bool cylinder = false;
      const auto marks = MarksFor(scene, i, round, &cylinder);
      if (!marks) continue;
      burst.push_back(RequestFor(cylinder, *marks, grab.value.frame_id()));
    }
    f.burst_size = burst.size();
    std::atomic<int> left{static_cast<int>(burst.size())};
    const auto start = Clock::now();
    for (const auto& request : burst)
      object.Call<igms::object::LocateResponse>(
          "igms.object.ObjectService.Locate", request, 60s,
          [&](const igms::net::Result<igms::object::LocateResponse>& r) {
            f.failures += !r.ok();
            if (left.fetch_sub(1) == 1) left.notify_one();
          });
    for (int n = left.load(); n != 0; n = left.load()) left.wait(n);
    f.burst_all.push_back(Ms(Clock::now() - start));
    const auto serial_start = Clock::now();
    for (const auto& request : burst)
      f.failures += !object
                         .CallSync<igms::object::LocateResponse>("igms.object.ObjectService.Locate",
                                                                 request, 60s)
                         .ok();
    f.burst_serial.push_back(Ms(Clock::now() - serial_start));
  }
}

void Print(const igms::site::Scene& scene, int rounds, const Figures& f) {
  std::printf(
      "Marks to model over TCP: igms-object-server and igms-video-server (sim, %dx%d) as\n"
      "processes on loopback; %d rounds of a grab and a Locate for each of the default\n"
      "testbed's objects; %d requests, %d found, %d errors.\n\n",
      scene.cameras.left.image_size().width, scene.cameras.left.image_size().height, rounds,
      f.requests, f.found, f.failures);
  std::printf("%-44s %5s %8s %8s %8s\n", "ms", "n", "p50", "p99", "max");
  Row("round trip, every request", f.rtt_all);
  Row("  first request after a grab (fetches frame)", f.rtt_first);
  Row("  later requests (frame cached)", f.rtt_cached);
  Row("server: locate", f.server_locate);
  Row("server: fetch from the video server", f.server_fetch);
  Row("offline Locate(), same marks, this process", f.offline);
  Row("  its CPU time (this thread)", f.offline_cpu);
  std::printf("\n%zu requests on one grab, sent at once (the server's workers share them):\n",
              f.burst_size);
  Row("  all answered (the frame fetched once)", f.burst_all);
  Row("  the same, one at a time (frame cached)", f.burst_serial);
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) < 1) load[0] = -1;
  std::printf(
      "\ntargets: round trip p50 < 10 ms, p99 < 30 ms (512x480); load average %.1f on %u cores\n",
      load[0], std::thread::hardware_concurrency());
}

int RunBenchmark(int argc, char** argv) {
  const int rounds = argc > 1 ? std::atoi(argv[1]) : 40;
  const std::filesystem::path self = std::filesystem::canonical("/proc/self/exe");
  const std::string bin = argc > 2 ? argv[2] : (self.parent_path().parent_path() / "bin").string();
  const std::string calibration = argc > 3 ? argv[3]
                                           : std::string(IGMS_SOURCE_DIR_DEFAULT) +
                                                 "/common/calibration/data/thesis_calibration.yaml";
  const auto cal = igms::calibration::LoadCalibration(calibration);
  if (!cal.ok()) {
    std::fprintf(stderr, "bench_object_latency: cannot load %s\n", calibration.c_str());
    return 2;
  }
  const std::string scratch =
      (std::filesystem::temp_directory_path() / ("igms_latency_" + std::to_string(::getpid())))
          .string();
  std::filesystem::create_directories(scratch);
  const auto servers = StartServers(bin, calibration, scratch);
  if (!servers) return 1;
  boost::asio::io_context io;
  auto work = boost::asio::make_work_guard(io);
  std::thread io_thread([&] { io.run(); });
  auto video_client = Connect(io, servers->video->port());
  auto object_client = Connect(io, servers->object->port());

  // The scene the sim backend renders by default, and the same marks offline.
  const igms::site::Scene scene = igms::site::DefaultTestbedScene();
  const igms::site::StereoImages images = igms::site::RenderStereo(scene);
  cv::setNumThreads(1);
  Figures figures;
  if (!SerialRounds(rounds, *video_client, *object_client, scene, images, figures)) return 1;
  BurstRounds(std::max(5, rounds / 4), *video_client, *object_client, scene, figures);
  object_client->Stop();
  video_client->Stop();
  work.reset();
  io.stop();
  io_thread.join();
  std::filesystem::remove_all(scratch);

  Print(scene, rounds, figures);
  return figures.failures ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  return igms::bench::MainReportingFailures(argc, argv, RunBenchmark);
}
