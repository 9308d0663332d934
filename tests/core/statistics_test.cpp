// Order statistics (core/statistics.h): the nearest-rank percentile against the textbook example
// and an integer-arithmetic reference, the mean.
#include "nestwalk/core/statistics.h"
#include "tests/common/nearest_rank.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace nestwalk {
namespace {

using test::nearestRank;


TEST(Percentile, TextbookExample) {
  // The nearest-rank example on five values (15, 20, 35, 40, 50).
  const std::vector<double> v = {50, 15, 40, 20, 35};
  EXPECT_EQ(percentile(v, 5), 15);
  EXPECT_EQ(percentile(v, 30), 20);
  EXPECT_EQ(percentile(v, 40), 20);
  EXPECT_EQ(percentile(v, 50), 35);
  EXPECT_EQ(percentile(v, 100), 50);
  EXPECT_EQ(percentile(v, 0), 15);
  EXPECT_EQ(percentile({}, 50), 0);
  EXPECT_EQ(percentile({7}, 99), 7);
}

TEST(Percentile, ExactRanksAreNotRoundedUp) {
  // 95 % of 20 values is rank 19 exactly; a floating 0.95 * 20 could round to rank 20.
  std::vector<double> v;
  for (int i = 1; i <= 20; ++i) v.push_back(i);
  EXPECT_EQ(percentile(v, 95), 19);
  for (int n : {1, 2, 3, 7, 10, 99, 100, 101, 1000, 1237})
    for (int p : {0, 1, 5, 10, 33, 50, 90, 95, 99, 100}) {
      std::vector<double> w;
      std::mt19937 rng(unsigned(n * 1000 + p));
      std::uniform_real_distribution<double> u(0, 100);
      for (int i = 0; i < n; ++i) w.push_back(u(rng));
      EXPECT_EQ(percentile(w, p), nearestRank(w, p)) << "n " << n << " p " << p;
    }
}

TEST(Mean, OfValuesAndOfNone) {
  EXPECT_EQ(mean({}), 0.0);
  EXPECT_EQ(mean({1.0, 2.0, 4.5}), 2.5);
}

}  // namespace
}  // namespace nestwalk
