#include "common/sim/marks.h"

#include <algorithm>
#include <random>

#include "common/sim/testbed.h"

namespace igms::site {

double FrontDepth(const Shape& shape, const geometry::ProjectiveCamera& camera) {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& p : OutlinePoints(shape, 90)) d = std::min(d, camera.Depth(p));
  return d;
}

std::optional<Marks> GenerateMarks(const Shape& shape, const geometry::ProjectiveCamera& left,
                                   uint64_t seed, const MarkModel& model) {
  double u0, v0, u1, v1;
  if (!ImageBounds(shape, left, u0, v0, u1, v1)) return std::nullopt;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> margin(model.margin_min, model.margin_max);
  const double depth_error =
      std::clamp(model.depth_sigma * normal(rng), -model.depth_clip, model.depth_clip);
  const double depth = FrontDepth(shape, left) + depth_error;
  if (depth <= 0) return std::nullopt;
  // A pixel's point at the chosen depth: depth grows linearly along each ray.
  const auto at_depth = [&](double u, double v) {
    const geometry::Ray ray = left.PixelRay({u, v});
    const double rate = left.Depth(ray.origin + ray.direction);
    return Eigen::Vector3d(ray.origin + ray.direction * (depth / rate));
  };
  const Eigen::Vector3d tl = at_depth(u0, v0), tr = at_depth(u1, v0), bl = at_depth(u0, v1);
  const Eigen::Vector3d eu = (tr - tl).normalized(), ev = (bl - tl).normalized();
  const double m_left = margin(rng), m_right = margin(rng), m_top = margin(rng),
               m_bottom = margin(rng);
  const Eigen::Vector3d br = at_depth(u1, v1);
  Marks marks = {tl - m_left * eu - m_top * ev, tr + m_right * eu - m_top * ev,
                 br + m_right * eu + m_bottom * ev, bl - m_left * eu + m_bottom * ev};
  for (auto& m : marks) m += model.lateral_sigma * (normal(rng) * eu + normal(rng) * ev);
  return marks;
}

}  // namespace igms::site
