#include "common/sim/thesis_reference.h"

#include <cmath>
#include <limits>

#include "common/calibration/thesis_calibration.h"

namespace igms::calibration {

const std::array<const char*, 10> kPrintedNames = {"ku", "kv", "u0",    "v0",  "x",
                                                   "y",  "z",  "theta", "phi", "psi"};

std::array<ThesisCamera, 2> ThesisCameras() {
  std::array<ThesisCamera, 2> cams;
  cams[0].name = "left";
  cams[0].C = ThesisCalibration().left.P;
  cams[0].printed = {-944.89, 1191.53, 323.6, 213.0, 20.85, 3.06, 3.77, 1.51, 0.043, 0.00};
  cams[1].name = "right";
  cams[1].C = ThesisCalibration().right.P;
  cams[1].printed = {-945.29, 1175.58, 309.1, 217.7, 16.89, 3.96, 3.74, 1.53, 0.039, 0.01};
  return cams;
}

std::array<double, 10> AsPrinted(const geometry::ThesisDecomposition& d) {
  return {d.ku,         d.kv,         d.u0,         d.v0,
          d.center.x(), d.center.y(), d.center.z(), d.printed_theta,
          d.phi,        d.printed_psi};
}

std::array<double, 10> AsArray(const PrintedDecomposition& p) {
  return {p.ku, p.kv, p.u0, p.v0, p.x, p.y, p.z, p.theta, p.phi, p.psi};
}

RoundingFit ClosestWithinRounding(const ThesisCamera& camera) {
  const auto target = AsArray(camera.printed);
  RoundingFit best;
  double best_cost = std::numeric_limits<double>::infinity();
  constexpr int kSteps = 20;
  constexpr double kStep = 0.005 / kSteps;
  for (int a = -kSteps; a <= kSteps; ++a) {
    for (int b = -kSteps; b <= kSteps; ++b) {
      for (int c = -kSteps; c <= kSteps; ++c) {
        geometry::Matrix34 C = camera.C;
        C(2, 0) += a * kStep;
        C(2, 1) += b * kStep;
        C(2, 2) += c * kStep;
        const auto d = geometry::DecomposeThesis(C);
        if (!d.ok()) continue;
        const auto v = AsPrinted(*d);
        double cost = 0;
        // Relative mismatch, with a floor so that near-zero angles still count.
        for (size_t k = 0; k < v.size(); ++k) {
          const double r = (v[k] - target[k]) / (0.01 * std::abs(target[k]) + 0.01);
          cost += r * r;
        }
        if (cost < best_cost) {
          best_cost = cost;
          best.C = C;
          best.decomposition = *d;
          best.max_row3_change = std::max({std::abs(a), std::abs(b), std::abs(c)}) * kStep;
        }
      }
    }
  }
  return best;
}

}  // namespace igms::calibration
