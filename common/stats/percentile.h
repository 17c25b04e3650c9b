// Percentiles of a sample, for the figures the tools, evaluations and benchmarks print.
#pragma once

#include <vector>

namespace igms::stats {

// The q-quantile (0 <= q <= 1) by linear interpolation between the two nearest order
// statistics: with the sample sorted as x[0] <= ... <= x[n-1] and h = q * (n - 1),
//   Percentile = x[floor(h)] + (h - floor(h)) * (x[floor(h) + 1] - x[floor(h)]).
// This is Hyndman and Fan's definition 7 (NumPy's and R's default): q = 0 is the minimum,
// q = 1 the maximum, q = 0.5 the median (the mean of the middle two when n is even).
// NaN values in the sample are left out (a failed measurement is not a figure); NaN when
// nothing is left or q is NaN; q outside [0, 1] is clamped to it.
double Percentile(std::vector<double> sample, double q);

// Percentile(sample, 0.5).
double Median(std::vector<double> sample);

}  // namespace igms::stats
