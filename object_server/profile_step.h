// A grey-level profile across an edge fitted as a model linear in its coefficients once the
// step's place is fixed (a limb's shading, a thin face's shade): the place searched coarse,
// then fine about the best (locate_shading_steps.cpp, locate_face_steps.cpp).
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <vector>

namespace igms::object {

template <int N>
struct ProfileStepFit {
  double at = 0, rss = std::numeric_limits<double>::infinity();
  Eigen::Matrix<double, N, 1> coef = Eigen::Matrix<double, N, 1>::Zero();
};

// The step's place e within +-reach (every `coarse` px, then every `fine` px about the best)
// whose least-squares fit of grey[k] to row(d_k, e), d_k = first + k * step, leaves the least
// residual sum of squares; with that fit's coefficients.
template <int N, class RowFn>
ProfileStepFit<N> FitProfileStep(const std::vector<double>& grey, double first, double step,
                                 double reach, double coarse, double fine, const RowFn& row) {
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;
  ProfileStepFit<N> best;
  double bb = 0;
  for (const double g : grey) bb += g * g;
  const auto try_at = [&](double e) {
    Mat AtA = Mat::Zero();
    Vec Atb = Vec::Zero();
    for (size_t k = 0; k < grey.size(); ++k) {
      const Vec r = row(first + static_cast<double>(k) * step, e);
      AtA += r * r.transpose();
      Atb += r * grey[k];
    }
    const Vec coef = AtA.ldlt().solve(Atb);
    const double rss = bb - coef.dot(Atb);
    if (rss < best.rss) {
      best.rss = rss;
      best.at = e;
      best.coef = coef;
    }
  };
  for (double e = -reach; e <= reach + 1e-9; e += coarse) try_at(e);
  const double centre = best.at;
  for (double e = centre - coarse + fine; e < centre + coarse - 1e-9; e += fine)
    if (std::abs(e - centre) > 1e-9) try_at(e);
  return best;
}

}  // namespace igms::object
