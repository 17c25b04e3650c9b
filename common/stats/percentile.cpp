#include "common/stats/percentile.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>

namespace igms::stats {

double Percentile(std::vector<double> sample, double q) {
  std::erase_if(sample, [](double x) { return std::isnan(x); });
  if (sample.empty() || std::isnan(q)) return std::numeric_limits<double>::quiet_NaN();
  std::sort(sample.begin(), sample.end());
  const double h = std::clamp(q, 0.0, 1.0) * static_cast<double>(sample.size() - 1);
  const auto i = static_cast<std::size_t>(std::floor(h));
  const double f = h - static_cast<double>(i);
  return i + 1 < sample.size() ? sample[i] * (1 - f) + sample[i + 1] * f : sample[i];
}

double Median(std::vector<double> sample) { return Percentile(std::move(sample), 0.5); }

}  // namespace igms::stats
