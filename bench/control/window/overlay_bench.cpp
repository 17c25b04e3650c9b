// The window's figures (docs/window.md), printed:
//  1. Registration: the simulated site's true solids drawn by the renderer (multisampled and
//     supersampled) against the simulated video drawn by the same renderer, at the zero pose
//     and two panned poses of the thesis's platform, without and with a lens (radial and
//     tangential distortion added to the simulated camera, undone by the renderer): the
//     sub-pixel 50% crossings of the outlines along rows and columns, median and 95th
//     percentile (the thesis saw up to 5 px, section 4.2). Then the same for the located
//     models: each object located by the object server's locator from marks the mark model
//     makes (seeded by --mark-seed, default 1) on the pair the cameras deliver at that pose
//     (lit, noisy, and through the lens in the lens rows), the found models drawn instead.
//  2. The frame time of side-by-side stereo at 1280 x 1024 per eye with 1, 100, 1,000 and
//     10,000 models, video uploaded each frame, in this machine's software GL.
//
//   bench_overlay [--quick] [--registration | --frames] [--mark-seed N] [--models N,N,...]
//                 [--cylinder-sides N]
//
// --registration or --frames prints only those figures; --quick draws fewer frames;
// --models the model counts of the frame times (default 1,100,1000,10000);
// --cylinder-sides the renderer's sides per cylinder (default 96).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <opencv2/imgproc.hpp>
#include <random>

#include "bench/bench_main.h"
#include "common/calibration/thesis_calibration.h"
#include "common/geometry/platform.h"
#include "common/sim/testbed.h"
#include "common/stats/percentile.h"
#include "control/render/gl.h"
#include "control/render/offscreen.h"
#include "control/render/renderer.h"
#include "control/render/stereo.h"
#include "tests/render/registration.h"

namespace igms::control::render {
namespace {

namespace reg = registration;
constexpr geometry::ImageSize kSize{512, 480};

cv::Mat DrawOne(Renderer& renderer, const DrawList& list, int eye, int factor, int samples) {
  auto target = RenderTarget::Make(kSize.width * factor, kSize.height * factor, samples);
  (*target)->Bind();
  renderer.Clear(kSize.width * factor, kSize.height * factor);
  renderer.DrawEye(list, eye, {0, 0, kSize.width * factor, kSize.height * factor});
  cv::Mat big = (*target)->Read();
  if (factor == 1) return big;
  cv::Mat small;
  cv::resize(big, small, cv::Size(kSize.width, kSize.height), 0, 0, cv::INTER_AREA);
  return small;
}

void Registration(Renderer& renderer, uint64_t mark_seed) {
  const auto& cal = calibration::ThesisCalibration();
  const site::Scene site_scene = site::DefaultTestbedScene();
  const site::Scene scene = reg::MaskScene(site_scene);
  geometry::Lens lens;
  lens.K << 945, 0, 323, 0, 1190, 213, 0, 0, 1;
  lens.dist = {-0.35, 0.2, 0.002, -0.0015, 0.0};
  const std::vector<std::vector<double>> poses = {{0, 0, 0}, {0.06, 0, 0}, {-0.05, 0.03, 0}};
  std::printf(
      "registration: the site's true solids, and the models its locator finds from marks "
      "(mark seed %llu), over its simulated video (px)\n",
      static_cast<unsigned long long>(mark_seed));
  std::printf("  %-20s %5s %-13s %8s %8s %9s %9s %8s\n", "pose (pan, tilt rad)", "lens", "models",
              "median", "p95", "crossings", "unpaired", "locate s");
  for (bool with_lens : {false, true}) {
    // Per row: 0 the true solids, 1 the located models.
    std::vector<double> all[2];
    int all_missing[2] = {0, 0}, all_found = 0, all_asked = 0;
    for (const auto& q : poses) {
      DrawList graphics[2];
      site::StereoCameras cameras;
      for (int eye = 0; eye < 2; ++eye) {
        const auto& c = eye == 0 ? cal.left : cal.right;
        const geometry::Matrix34 P = geometry::CameraAtPose(c.P, *cal.platform, q);
        (eye == 0 ? cameras.left : cameras.right) = with_lens
                                                        ? geometry::ProjectiveCamera(P, kSize, lens)
                                                        : geometry::ProjectiveCamera(P, kSize);
        for (auto& g : graphics) {
          g.eyes[eye].P = P;
          g.eyes[eye].size = kSize;
          g.lit = false;
        }
      }
      graphics[0].models = reg::ModelsOf(scene);
      // The locator sees what the cameras deliver at this pose (through the lens, if any).
      const auto t0 = std::chrono::steady_clock::now();
      const cv::Mat left = reg::CameraImage(site_scene, cameras.left, 0);
      const cv::Mat right = reg::CameraImage(site_scene, cameras.right, 1);
      const reg::Located located = reg::LocateModels(site_scene, cameras, left, right, mark_seed);
      const double locate_s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      graphics[1].models = located.models;
      all_found += located.found;
      all_asked += located.asked;
      std::vector<double> errors[2];
      int missing[2] = {0, 0};
      for (int eye = 0; eye < 2; ++eye) {
        const auto& camera = eye == 0 ? cameras.left : cameras.right;
        const geometry::ProjectiveCamera ideal(camera.P(), kSize);
        const cv::Mat truth = reg::TruthCoverage(scene, ideal);
        cv::Mat video8;
        const cv::Mat observed = with_lens ? reg::Distorted(truth, camera) : truth;
        observed.convertTo(video8, CV_8U, 255.0);
        DrawList video;
        video.eyes[eye].P = camera.P();
        video.eyes[eye].size = kSize;
        video.eyes[eye].video = video8;
        if (with_lens) video.eyes[eye].lens = lens;
        const cv::Mat drawn_video = reg::CoverageOf(DrawOne(renderer, video, eye, 1, 1));
        for (int k = 0; k < 2; ++k) {
          const cv::Mat drawn = reg::CoverageOf(DrawOne(renderer, graphics[k], eye, 4, 4));
          int m = 0;
          const auto e = reg::EdgeErrors(drawn_video, drawn, &m);
          errors[k].insert(errors[k].end(), e.begin(), e.end());
          missing[k] += m;
        }
      }
      char pose[64];
      std::snprintf(pose, sizeof(pose), "(%.2f, %.2f)", q[0], q[1]);
      for (int k = 0; k < 2; ++k) {
        all[k].insert(all[k].end(), errors[k].begin(), errors[k].end());
        all_missing[k] += missing[k];
        char models[32];
        if (k == 0) {
          std::snprintf(models, sizeof(models), "true");
        } else {
          std::snprintf(models, sizeof(models), "located %d/%d", located.found, located.asked);
        }
        char secs[16] = "";
        if (k == 1) std::snprintf(secs, sizeof(secs), "%.1f", locate_s);
        std::printf("  %-20s %5s %-13s %8.3f %8.3f %9zu %9d %8s\n", pose, with_lens ? "yes" : "no",
                    models, stats::Percentile(errors[k], 0.5), stats::Percentile(errors[k], 0.95),
                    errors[k].size(), missing[k], secs);
      }
      for (const auto& r : located.refused) std::printf("    refused %s\n", r.c_str());
    }
    for (int k = 0; k < 2; ++k) {
      char models[32];
      if (k == 0) {
        std::snprintf(models, sizeof(models), "true");
      } else {
        std::snprintf(models, sizeof(models), "located %d/%d", all_found, all_asked);
      }
      std::printf("  %-20s %5s %-13s %8.3f %8.3f %9zu %9d\n", "all poses", with_lens ? "yes" : "no",
                  models, stats::Percentile(all[k], 0.5), stats::Percentile(all[k], 0.95),
                  all[k].size(), all_missing[k]);
    }
  }
}

void FrameTimes(Renderer& renderer, bool quick, const std::vector<int>& counts) {
  const auto& cal = calibration::ThesisCalibration();
  // The thesis's cameras scaled to 1280 x 1024 (the BOOM2C's channels, section 2.1.3).
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  S(0, 0) = 1280.0 / 512;
  S(1, 1) = 1024.0 / 480;
  const geometry::ImageSize eye{1280, 1024};
  DrawList list;
  for (int e = 0; e < 2; ++e) {
    list.eyes[e].P = S * (e == 0 ? cal.left.P : cal.right.P);
    list.eyes[e].size = eye;
    list.eyes[e].video = cv::Mat(1024, 1280, CV_8UC3, cv::Scalar(60, 90, 120));
  }
  list.hud = {{"IGMS  verification   [side-by-side]   solid"}, {"the frame-time benchmark"}};
  const auto size = FrameSize(StereoMode::kSideBySide, eye);
  auto target = RenderTarget::Make(size.width, size.height, 4);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> x(6, 36), y(-84, -30), s(0.3, 3);
  std::printf(
      "frame time, side by side at 2 x 1280 x 1024, 4x multisampling, video uploaded "
      "every frame (%s):\n",
      reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
  std::printf("  %8s %10s %10s %10s\n", "models", "solid ms", "wire ms", "fps solid");
  for (int count : counts) {
    list.models.clear();
    for (int i = 0; i < count; ++i) {
      DrawModel m;
      m.kind = i % 2 ? DrawModel::Kind::kCylinder : DrawModel::Kind::kBox;
      m.center = {x(rng), y(rng), 2};
      m.size = {s(rng), s(rng), s(rng)};
      m.radius = 0.5 * s(rng);
      m.height = 2 * s(rng);
      list.models.push_back(m);
    }
    double ms[2] = {0, 0};
    for (int wire = 0; wire < 2; ++wire) {
      list.wireframe = wire == 1;
      const int frames = quick ? 2 : (count >= 10000 ? 3 : count >= 1000 ? 10 : 30);
      (*target)->Bind();
      DrawStereo(renderer, list, StereoMode::kSideBySide, size.width, size.height);  // warm
      glFinish();
      const auto t0 = std::chrono::steady_clock::now();
      for (int f = 0; f < frames; ++f) {
        for (auto& e : list.eyes) e.video_id = static_cast<uint64_t>(f) + 1;  // new video
        DrawStereo(renderer, list, StereoMode::kSideBySide, size.width, size.height);
        glFinish();
      }
      ms[wire] =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() /
          frames;
    }
    std::printf("  %8d %10.1f %10.1f %10.1f\n", count, ms[0], ms[1], 1000.0 / ms[0]);
  }
}

}  // namespace
}  // namespace igms::control::render

namespace {

int RunBenchmark(int argc, char** argv) {
  bool quick = false, registration = true, frames = true;
  uint64_t mark_seed = 1;
  std::vector<int> counts = {1, 100, 1000, 10000};
  int sides = 0;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--registration") == 0) {
      frames = false;
    } else if (std::strcmp(argv[i], "--frames") == 0) {
      registration = false;
    } else if (std::strcmp(argv[i], "--mark-seed") == 0 && i + 1 < argc) {
      mark_seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (std::strcmp(argv[i], "--cylinder-sides") == 0 && i + 1 < argc) {
      sides = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--models") == 0 && i + 1 < argc) {
      counts.clear();
      for (char* p = argv[++i]; *p;) {
        counts.push_back(static_cast<int>(std::strtol(p, &p, 10)));
        if (*p == ',') ++p;
      }
    } else {
      std::fprintf(stderr,
                   "usage: bench_overlay [--quick] [--registration | --frames] "
                   "[--mark-seed N] [--models N,N,...] [--cylinder-sides N]\n");
      return 2;
    }
  }
  auto context = igms::control::render::OffscreenContext::Make();
  if (!context.ok()) {
    std::fprintf(stderr, "bench_overlay: %s\n", context.error().c_str());
    return 1;
  }
  auto renderer = igms::control::render::Renderer::Make();
  if (!renderer.ok()) {
    std::fprintf(stderr, "bench_overlay: %s\n", renderer.error().c_str());
    return 1;
  }
  if (sides > 0) (*renderer)->cylinder_segments = sides;
  if (registration) igms::control::render::Registration(**renderer, mark_seed);
  if (frames) igms::control::render::FrameTimes(**renderer, quick, counts);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return igms::bench::MainReportingFailures(argc, argv, RunBenchmark);
}
