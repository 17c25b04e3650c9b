// Video server figures, each beside its baseline measured in the same run:
//  1. grab to edges ready (the clock starts when the captured pair is available; capture is
//     timed on its own) for 512x480 and 1920x1080 pairs, beside a bare cv::Canny on the same
//     images, with and without the same Gaussian smoothing;
//  2. live video at 1280x1024 from the real server process to 1 and 4 subscribers;
//  3. the server process's peak resident memory with its default frame store full of
//     1920x1080 pairs, however many grabs it has taken.
// Images: Debian's opencv-doc aloe pair, resized.
// Usage: bench_video [--quick | --memory]; IGMS_BENCH_GRABS=N sets the grabs of the memory run.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_main.h"
#include "common/base/clock.h"
#include "common/net/mailbox.h"
#include "common/stats/percentile.h"
#include "igms/video.pb.h"
#include "tests/support/video_server_process.h"
#include "video_server/edge_pipeline.h"
#include "video_server/files_capture.h"
#include "video_server/frame_id.h"
#include "video_server/frame_store.h"

namespace {

using namespace igms::video;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

const std::string kData = "/usr/share/doc/opencv-doc/examples/data/";

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

using igms::stats::Median;
using igms::stats::Percentile;

cv::Mat Resized(const std::string& name, cv::Size size) {
  cv::Mat grey = cv::imread(kData + name, cv::IMREAD_GRAYSCALE), out;
  cv::resize(grey, out, size, 0, 0, cv::INTER_AREA);
  return out;
}

void EdgeFigures(cv::Size size, int rounds) {
  const cv::Mat left = Resized("aloeL.jpg", size), right = Resized("aloeR.jpg", size);
  const EdgeOptions options;
  std::vector<double> canny, blur_canny, ready, capture;
  FrameIdSource ids;
  FrameStore store(16, ids.first());
  EdgePipeline pipeline(options, 2);
  int edge_pixels = 0;
  // Baselines and the server's path alternate round by round, so a machine shared with
  // other work slows them alike.
  for (int i = 0; i < rounds; ++i) {
    // Baselines: the pair one image after the other on this thread, as a plain program would.
    cv::Mat e1, e2;
    auto t0 = Clock::now();
    cv::Canny(left, e1, options.low_threshold, options.high_threshold, 3, true);
    cv::Canny(right, e2, options.low_threshold, options.high_threshold, 3, true);
    canny.push_back(Ms(Clock::now() - t0));
    cv::Mat s1, s2;
    t0 = Clock::now();
    cv::GaussianBlur(left, s1, cv::Size(0, 0), options.sigma, options.sigma, cv::BORDER_REPLICATE);
    cv::Canny(s1, e1, options.low_threshold, options.high_threshold, 3, true);
    cv::GaussianBlur(right, s2, cv::Size(0, 0), options.sigma, options.sigma, cv::BORDER_REPLICATE);
    cv::Canny(s2, e2, options.low_threshold, options.high_threshold, 3, true);
    blur_canny.push_back(Ms(Clock::now() - t0));

    // The server's path: a pair arrives (here a copy, as the files backend delivers it), is
    // stored under a new id, and its edges are started on the pool; the clock stops when the
    // edges (maps and directions of both sides) are ready.
    t0 = Clock::now();
    StereoImages images;
    images.left = left.clone();
    images.right = right.clone();
    images.left_capture_unix_ns = images.right_capture_unix_ns = igms::UnixNs();
    capture.push_back(Ms(Clock::now() - t0));
    t0 = Clock::now();
    auto record = store.Insert(ids.Next(), std::move(images));
    pipeline.Start(record);
    auto edges = record->WaitEdges(60s);
    ready.push_back(Ms(Clock::now() - t0));
    edge_pixels = edges->left.edge_count() + edges->right.edge_count();
  }
  const double r = Median(ready), c = Median(canny), bc = Median(blur_canny);
  std::printf(
      "edges %4dx%-4d pair: grab->edges ready median %.2f ms (p90 %.2f)  | bare cv::Canny x2 "
      "%.2f ms (ratio %.2f) | GaussianBlur+cv::Canny x2 %.2f ms (ratio %.2f) | capture copy "
      "%.2f ms | %d edge px | opencv threads %d\n",
      size.width, size.height, r, Percentile(ready, 0.9), c, r / c, bc, r / bc, Median(capture),
      edge_pixels, cv::getNumThreads());
}

struct Server {
  igms::video::testing::ScratchDir scratch;
  std::unique_ptr<igms::video::testing::ServerProcess> process;
  uint16_t port = 0;
};

std::unique_ptr<Server> StartServer(cv::Size size, std::vector<std::string> extra) {
  auto server = std::make_unique<Server>();
  const std::string left = server->scratch.File("left.png"),
                    right = server->scratch.File("right.png");
  cv::imwrite(left, Resized("aloeL.jpg", size));
  cv::imwrite(right, Resized("aloeR.jpg", size));
  // The server's log goes to a file of the test support's, where its port is read from.
  std::vector<std::string> args = {"--set", "processes.video.files.left=" + left, "--set",
                                   "processes.video.files.right=" + right};
  args.insert(args.end(), extra.begin(), extra.end());
  server->process = std::make_unique<igms::video::testing::ServerProcess>(args);
  server->port = server->process->WaitPort();
  if (server->port == 0) throw std::runtime_error("igms-video-server did not start");
  return server;
}

void LiveFigures(int subscribers, double seconds) {
  auto server = StartServer(cv::Size(1280, 1024), {});
  struct Sub {
    std::unique_ptr<igms::video::testing::TestClient> client;
    std::atomic<int> frames{0};
    std::atomic<uint64_t> first_seq{0}, last_seq{0};
    std::mutex mutex;
    std::vector<double> age_ms;
  };
  std::vector<std::unique_ptr<Sub>> subs;
  LiveRequest request;
  request.set_fps(60);
  request.set_encoding(RAW);
  for (int i = 0; i < subscribers; ++i) {
    auto sub = std::make_unique<Sub>();
    sub->client = std::make_unique<igms::video::testing::TestClient>(server->port);
    (*sub->client)->WaitConnected(5s);
    subs.push_back(std::move(sub));
  }
  const auto warmup = Clock::now() + 1s;
  for (auto& sub : subs) {
    Sub* s = sub.get();
    (*s->client)
        ->Subscribe<LiveFrame>(
            "igms.video.VideoService.Live", request, [s, warmup](const LiveFrame& frame) {
              if (Clock::now() < warmup) return;
              if (s->frames++ == 0) s->first_seq = frame.sequence();
              s->last_seq = frame.sequence();
              std::lock_guard lock(s->mutex);
              s->age_ms.push_back(static_cast<double>(igms::UnixNs() - frame.capture_unix_ns()) /
                                  1e6);
            });
  }
  std::this_thread::sleep_for(1s + std::chrono::duration<double>(seconds));
  for (auto& sub : subs) sub->client.reset();
  std::vector<double> fps, ages;
  uint64_t skipped = 0;
  for (auto& sub : subs) {
    fps.push_back(sub->frames / seconds);
    ages.insert(ages.end(), sub->age_ms.begin(), sub->age_ms.end());
    if (sub->frames > 0) skipped += (sub->last_seq - sub->first_seq + 1) - sub->frames;
  }
  std::printf(
      "live 1280x1024 grey pair raw, 60 fps asked, %d subscriber(s): fps per subscriber min %.1f "
      "median %.1f | capture->received median %.1f ms p99 %.1f ms (one frame is %.1f ms) | "
      "captures skipped by latest-only %llu\n",
      subscribers, *std::min_element(fps.begin(), fps.end()), Median(fps), Median(ages),
      Percentile(ages, 0.99), 1000.0 / 60, static_cast<unsigned long long>(skipped));
}

long StatusKb(pid_t pid, const std::string& key) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key + ":", 0) == 0) return std::stol(line.substr(key.size() + 1));
  }
  return -1;
}

void MemoryFigures(int grabs) {
  auto server = StartServer(cv::Size(1920, 1080), {});
  igms::video::testing::TestClient client(server->port);
  client->WaitConnected(5s);
  const long start_kb = StatusKb(server->process->pid(), "VmRSS");
  StatusResponse status;
  std::vector<long> hwm_at;
  for (int i = 1; i <= grabs; ++i) {
    auto grab = client->CallSync<GrabResponse>("igms.video.VideoService.Grab", GrabRequest{}, 30s);
    if (!grab.ok()) throw std::runtime_error(grab.status.ToString());
    if (i % 8 == 0) {  // let the edges keep up, as an operator's grabs would
      GetEdgesRequest edges;
      edges.set_frame_id(grab.value.frame_id());
      edges.mutable_region()->set_width(16);
      edges.mutable_region()->set_height(16);
      client->CallSync<GetEdgesResponse>("igms.video.VideoService.GetEdges", edges, 30s);
    }
    if (i == 16 || i == grabs / 2 || i == grabs)
      hwm_at.push_back(StatusKb(server->process->pid(), "VmHWM"));
  }
  auto s =
      client->CallSync<StatusResponse>("igms.video.VideoService.GetStatus", StatusRequest{}, 10s);
  status = s.value;
  std::printf(
      "memory, 1920x1080 grey pairs, store capacity %u: RSS at start %.1f MB; peak RSS after 16 "
      "grabs %.1f MB, after %d %.1f MB, after %d %.1f MB; store holds %u frames, %.1f MB "
      "(images + edges); evictions %llu\n",
      status.capacity(), static_cast<double>(start_kb) / 1024.0,
      static_cast<double>(hwm_at[0]) / 1024.0, grabs / 2, static_cast<double>(hwm_at[1]) / 1024.0,
      grabs, static_cast<double>(hwm_at[2]) / 1024.0, status.frames_held(),
      static_cast<double>(status.bytes_held()) / 1048576.0,
      static_cast<unsigned long long>(status.evictions()));
}

int RunBenchmark(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);
  if (!getenv("IGMS_BIN_DIR")) setenv("IGMS_BIN_DIR", IGMS_DEFAULT_BIN_DIR, 0);
  const bool quick = argc > 1 && std::string(argv[1]) == "--quick";
  const bool memory_only = argc > 1 && std::string(argv[1]) == "--memory";
  if (!std::filesystem::exists(kData + "aloeL.jpg")) {
    std::fprintf(stderr, "bench_video: needs opencv-doc (deploy/install-deps.sh)\n");
    return 2;
  }
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) == 3) {
    std::printf("machine: %u cores, load average %.1f (figures drift when other work runs)\n",
                std::thread::hardware_concurrency(), load[0]);
  }
  try {
    if (!memory_only) {
      EdgeFigures(cv::Size(512, 480), quick ? 30 : 200);
      EdgeFigures(cv::Size(1920, 1080), quick ? 10 : 60);
      LiveFigures(1, quick ? 2.0 : 5.0);
      LiveFigures(4, quick ? 2.0 : 5.0);
    }
    const char* grabs = getenv("IGMS_BENCH_GRABS");
    MemoryFigures(grabs ? std::max(48, atoi(grabs)) : quick ? 48 : 160);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_video: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return igms::bench::MainReportingFailures(argc, argv, RunBenchmark);
}
