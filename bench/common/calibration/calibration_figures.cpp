// Prints the geometry and calibration figures: the thesis's decomposition reproduced value by
// value, chessboard calibration beside OpenCV's stereo_calib sample (run in the same process
// on the same corners), DLT residuals with 0.5 px noise on 20 synthetic points, platform
// calibration recovery, OpenGL registration and triangulation uncertainty.
//   build/bench/calibration_figures [--no-chessboard]
#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <random>
#include <string>
#include <vector>

#include "bench/bench_main.h"
#include "common/calibration/chessboard.h"
#include "common/calibration/dlt.h"
#include "common/geometry/gl_camera.h"
#include "common/geometry/triangulation.h"
#include "common/sim/synthetic_platform.h"
#include "common/sim/thesis_reference.h"

namespace ic = igms::calibration;
namespace ig = igms::geometry;

namespace {

void ThesisDecomposition() {
  std::printf("== Thesis decomposition (Cooke, section 4.2, equations 4.1 and 4.2)\n");
  for (const auto& cam : ic::ThesisCameras()) {
    const auto direct = ic::AsPrinted(*ig::DecomposeThesis(cam.C));
    const auto fit = ic::ClosestWithinRounding(cam);
    const auto within = ic::AsPrinted(fit.decomposition);
    const auto printed = ic::AsArray(cam.printed);
    std::printf(
        "%s camera: printed | from the printed matrix | third row moved <= %.4f (within its "
        "rounding)\n",
        cam.name.c_str(), fit.max_row3_change);
    for (size_t k = 0; k < printed.size(); ++k) {
      std::printf("  %-6s %10.3f | %10.3f (%+8.3f) | %10.3f (%+8.3f)\n", ic::kPrintedNames[k],
                  printed[k], direct[k], direct[k] - printed[k], within[k], within[k] - printed[k]);
    }
    std::printf("  third row used: [%.5f %.5f %.5f]; skew %.5f rad\n", fit.C(2, 0), fit.C(2, 1),
                fit.C(2, 2), fit.decomposition.skew);
  }
}

void Chessboard() {
  std::printf(
      "\n== Chessboard stereo calibration, Debian opencv-doc left01..right14 (13 pairs, 9x6)\n");
  std::vector<std::string> left, right;
  for (int i = 1; i <= 14; ++i) {
    if (i == 10) continue;
    char name[96];
    std::snprintf(name, sizeof name, "/usr/share/doc/opencv-doc/examples/data/left%02d.jpg", i);
    left.push_back(name);
    std::snprintf(name, sizeof name, "/usr/share/doc/opencv-doc/examples/data/right%02d.jpg", i);
    right.push_back(name);
  }
  using P = ic::ChessboardOptions::Procedure;
  const std::pair<P, const char*> runs[] = {{P::kOpenCvSample, "OpenCV stereo_calib procedure"},
                                            {P::kFixed, "ours, intrinsics fixed"},
                                            {P::kJoint, "ours, joint refinement (default)"}};
  std::printf("  %-34s %6s %10s %10s %11s %12s\n", "procedure", "pairs", "left rms", "right rms",
              "stereo rms", "epipolar err");
  std::printf("  %-34s %6s %10s %10s %11.3f %12.3f\n", "OpenCV sample, published", "13", "-", "-",
              0.634, 0.445);
  for (const auto& [proc, name] : runs) {
    ic::ChessboardOptions options;
    options.procedure = proc;
    const auto r = ic::CalibrateChessboard(left, right, options);
    if (!r.ok()) {
      std::printf("  %-34s failed: %s\n", name, r.error().c_str());
      continue;
    }
    std::printf("  %-34s %6d %10.3f %10.3f %11.3f %12.3f\n", name, r->pairs_used, r->left_rms,
                r->right_rms, r->stereo_rms, r->epipolar_error);
  }
  std::printf(
      "  (epipolar error as the sample computes it: both images' distances summed per corner "
      "pair)\n");
}

void Dlt() {
  std::printf("\n== DLT calibration, 20 synthetic points, 0.5 px Gaussian noise (100 trials)\n");
  // The thesis-like camera (512x480, about 25 degrees) with the world origin 30 in in front.
  Eigen::Matrix3d K;
  K << 1150, 0, 255.5, 0, 1173, 239.5, 0, 0, 1;
  const Eigen::Vector3d c(-30, 2, 6), target(30, 0, 2);
  const Eigen::Vector3d z = (target - c).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R << x.transpose(), y.transpose(), z.transpose();
  ig::Matrix34 Rt;
  Rt << R, -R * c;
  const ig::ProjectiveCamera cam(K * Rt, {512, 480});
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> ux(6, 54), uy(-6, 6), uz(0, 10);
  std::normal_distribution<double> noise(0, 0.5);
  auto sample = [&](int n, bool noisy) {
    std::vector<ic::Correspondence> pts;
    while (static_cast<int>(pts.size()) < n) {
      const Eigen::Vector3d X(ux(rng), uy(rng), uz(rng));
      const auto px = cam.Project(X);
      if (!px || !cam.InImage(*px)) continue;
      pts.push_back(
          {X, *px + (noisy ? Eigen::Vector2d(noise(rng), noise(rng)) : Eigen::Vector2d::Zero())});
    }
    return pts;
  };
  for (auto method : {ic::DltMethod::kThesis, ic::DltMethod::kNormalized}) {
    double rms = 0, truth_err = 0;
    std::vector<double> first;
    for (int t = 0; t < 100; ++t) {
      const auto pts = sample(20, true);
      const auto r = ic::CalibrateDlt(pts, method);
      if (t == 0) first = r->residuals;
      rms += r->rms / 100;
      const auto check = sample(200, false);
      double e = 0;
      for (const auto& p : check)
        e += (*ig::ProjectiveCamera(r->P, {}).Project(p.world) - p.pixel).squaredNorm();
      truth_err += std::sqrt(e / static_cast<double>(check.size())) / 100;
    }
    std::printf(
        "  %-10s mean residual rms %.3f px; fitted camera vs truth %.3f px rms over the image\n",
        ic::ToString(method), rms, truth_err);
    std::printf("    trial 1 residuals (px):");
    for (double r : first) std::printf(" %.2f", r);
    std::printf("\n");
  }
  std::printf(
      "  (expected residual rms for 40 equations and 11 unknowns: 0.5 * sqrt(2 * 29 / 40) = %.3f "
      "px)\n",
      0.5 * std::sqrt(2.0 * 29 / 40));
}

void Platform() {
  std::printf("\n== Platform calibration (DH pan-tilt-roll), synthetic head, 27 poses\n");
  for (double noise : {0.3, 1.0}) {
    const auto s = ic::MakePlatformScenario(noise, 1);
    const auto before = ic::CompareToTruth(s, s.nominal, 2);
    for (bool scales : {false, true}) {
      ic::PlatformCalibrationOptions options;
      options.estimate_scales = scales;
      const auto r = ic::CalibratePlatform(s.P0[0], s.P0[1], s.nominal, s.observations, options);
      const auto after = ic::CompareToTruth(s, r->model, 2);
      std::printf(
          "  noise %.1f px, %zu obs, scales %-5s: rms %.3f -> %.3f px (%d it); axes %.4f deg / "
          "%.4f in; "
          "scales %.3f%%; prediction %.3f -> %.4f px\n",
          noise, s.observations.size(), scales ? "fit" : "fixed", r->initial_rms, r->rms,
          r->iterations, after.max_axis_angle_deg, after.max_axis_offset,
          after.max_scale_error * 100, before.prediction_rms_px, after.prediction_rms_px);
    }
  }
}

void Registration() {
  std::printf("\n== OpenGL registration and triangulation uncertainty (thesis cameras)\n");
  double worst = 0;
  for (const auto& cam : ic::ThesisCameras()) {
    const ig::ProjectiveCamera pc(cam.C, {512, 480});
    const auto gl = ig::MakeGlCamera(cam.C, {512, 480}, 6, 200);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0, 511), v(0, 479), d(12, 150);
    for (int i = 0; i < 10000; ++i) {
      const ig::Ray ray = pc.PixelRay({u(rng), v(rng)});
      const Eigen::Vector3d X = ray.At(d(rng) / ray.direction.dot(pc.ViewDirection()));
      worst = std::max(worst, (*ig::GlPixel(*gl, {512, 480}, X) - *pc.Project(X)).norm());
    }
  }
  std::printf("  OpenGL pixel vs P pixel, 20000 points: max %.2e px\n", worst);
  const auto cams = ic::ThesisCameras();
  const ig::ProjectiveCamera L(cams[0].C, {512, 480}), R(cams[1].C, {512, 480});
  for (double depth : {36.0, 60.0, 84.0}) {
    const Eigen::Vector3d X = L.Center() + depth * L.ViewDirection();
    const auto t = ig::Triangulate(L.P(), R.P(), *L.Project(X), *R.Project(X),
                                   ig::TriangulationMethod::kRefined, {.pixel_sigma = 0.5});
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(t->covariance);
    std::printf("  point at %.0f in, 0.5 px noise: 1-sigma axes %.3f / %.3f / %.3f in\n", depth,
                std::sqrt(eig.eigenvalues()[2]), std::sqrt(eig.eigenvalues()[1]),
                std::sqrt(eig.eigenvalues()[0]));
  }
}

int RunBenchmark(int argc, char** argv) {
  const bool chessboard = !(argc > 1 && std::strcmp(argv[1], "--no-chessboard") == 0);
  ThesisDecomposition();
  if (chessboard) Chessboard();
  Dlt();
  Platform();
  Registration();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return igms::bench::MainReportingFailures(argc, argv, RunBenchmark);
}
