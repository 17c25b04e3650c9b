#include "common/stats/percentile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace igms::stats {
namespace {

// The definition: linear interpolation between order statistics at h = q * (n - 1).
TEST(Percentile, InterpolatesBetweenOrderStatistics) {
  const std::vector<double> one_to_ten = {7, 3, 10, 1, 5, 9, 2, 8, 4, 6};  // order does not matter
  EXPECT_DOUBLE_EQ(Percentile(one_to_ten, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(Percentile(one_to_ten, 0.5), 5.5);  // h = 4.5: between 5 and 6
  EXPECT_DOUBLE_EQ(Percentile(one_to_ten, 0.9), 9.1);  // h = 8.1
  EXPECT_DOUBLE_EQ(Percentile(one_to_ten, 0.99), 9.91);
  EXPECT_DOUBLE_EQ(Percentile(one_to_ten, 1.0), 10.0);
  EXPECT_DOUBLE_EQ(Percentile({0, 100}, 0.25), 25.0);
}

TEST(Percentile, MatchesNumpysDefaultOnAnUnevenSample) {
  // numpy.percentile([0.5, 1, 4, 16, 64], [10, 50, 75, 95]) = [0.7, 4, 16, 54.4]
  const std::vector<double> v = {16, 0.5, 64, 1, 4};
  EXPECT_DOUBLE_EQ(Percentile(v, 0.10), 0.7);
  EXPECT_DOUBLE_EQ(Percentile(v, 0.50), 4.0);
  EXPECT_DOUBLE_EQ(Percentile(v, 0.75), 16.0);
  EXPECT_NEAR(Percentile(v, 0.95), 54.4, 1e-12);
}

TEST(Percentile, OneValueIsEveryPercentile) {
  for (double q : {0.0, 0.3, 0.99, 1.0}) EXPECT_EQ(Percentile({2.5}, q), 2.5);
}

TEST(Percentile, ClampsQToZeroOne) {
  EXPECT_EQ(Percentile({1, 2, 3}, -0.5), 1.0);
  EXPECT_EQ(Percentile({1, 2, 3}, 1.5), 3.0);
}

TEST(Percentile, NothingToMeasureIsNan) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(Percentile({}, 0.5)));
  EXPECT_TRUE(std::isnan(Percentile({nan, nan}, 0.5)));
  EXPECT_TRUE(std::isnan(Percentile({1, 2}, nan)));
}

TEST(Percentile, LeavesNanValuesOut) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_DOUBLE_EQ(Percentile({nan, 3, 1, nan, 2}, 0.5), 2.0);
  EXPECT_DOUBLE_EQ(Percentile({nan, 3, 1, nan, 2}, 1.0), 3.0);
}

TEST(Median, IsTheMiddleOrTheMeanOfTheMiddleTwo) {
  EXPECT_DOUBLE_EQ(Median({5, 1, 3}), 3.0);
  EXPECT_DOUBLE_EQ(Median({4, 1, 3, 2}), 2.5);
}

}  // namespace
}  // namespace igms::stats
