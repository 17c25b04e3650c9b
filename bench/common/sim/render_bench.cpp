// Simulator speed: 512 x 480 stereo pairs of the default testbed scene rendered on one core,
// beside a bare pass that only writes every pixel (the floor any renderer pays).
// Target: a stereo pair at 30 frames/s or better on one core.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <exception>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "bench/bench_main.h"
#include "common/sim/renderer.h"
#include "common/sim/testbed.h"
#include "common/stats/percentile.h"

namespace {

using igms::stats::Median;

// CPU time of this thread: the machine is shared, so wall time alone overstates the cost.
double CpuMs() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

int RunBenchmark(int argc, char** argv) {
  cv::setNumThreads(1);
  using Clock = std::chrono::steady_clock;
  igms::site::Scene scene = igms::site::DefaultTestbedScene();
  if (argc > 1) {
    const auto pair = igms::site::RenderStereo(scene);
    cv::imwrite(std::string(argv[1]) + "_left.png", pair.left);
    cv::imwrite(std::string(argv[1]) + "_right.png", pair.right);
  }
  const int runs = 40;
  std::vector<double> pair_ms, pair_cpu_ms, radiance_ms, sensor_ms, fill_ms;
  for (int i = 0; i < runs; ++i) {
    scene.sensor.seed = i + 1;
    auto t0 = Clock::now();
    const double c0 = CpuMs();
    const auto pair = igms::site::RenderStereo(scene);
    pair_cpu_ms.push_back(CpuMs() - c0);
    auto t1 = Clock::now();
    const cv::Mat rad = igms::site::RenderRadiance(scene, scene.cameras.left);
    auto t2 = Clock::now();
    const cv::Mat img = igms::site::ApplySensor(rad, scene.sensor, 0);
    auto t3 = Clock::now();
    cv::Mat fill(480, 512, CV_32F);
    for (int y = 0; y < fill.rows; ++y)
      for (int x = 0; x < fill.cols; ++x) fill.at<float>(y, x) = static_cast<float>(x ^ y ^ i);
    auto t4 = Clock::now();
    auto ms = [](auto a, auto b) {
      return std::chrono::duration<double, std::milli>(b - a).count();
    };
    pair_ms.push_back(ms(t0, t1));
    radiance_ms.push_back(ms(t1, t2));
    sensor_ms.push_back(ms(t2, t3));
    fill_ms.push_back(ms(t3, t4));
    if (pair.left.empty() || img.empty()) return 1;
  }
  std::printf("simulated site, default testbed scene (%zu objects), 512x480, one core, %d runs\n",
              scene.objects.size(), runs);
  std::printf("  stereo pair (render + sensor), median  %7.2f ms  = %6.1f pairs/s (target 30)\n",
              Median(pair_ms), 1000.0 / Median(pair_ms));
  std::printf("  stereo pair, CPU time of the thread     %7.2f ms  = %6.1f pairs/s\n",
              Median(pair_cpu_ms), 1000.0 / Median(pair_cpu_ms));
  std::printf("  one image: ray casting + anti-aliasing  %7.2f ms\n", Median(radiance_ms));
  std::printf("  one image: sensor (blur, noise, 8 bits) %7.2f ms\n", Median(sensor_ms));
  std::printf("  baseline: writing every pixel once       %7.2f ms\n", Median(fill_ms));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return igms::bench::MainReportingFailures(argc, argv, RunBenchmark);
}
