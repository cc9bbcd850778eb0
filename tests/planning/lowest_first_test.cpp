// lowest_first on made-up items: floors below values by random gaps, many near-ties, every
// number of threads. What may be left out is exactly what floor_decides allows against the true
// smallest value; the smallest value and every negative one are always found.
#include "marsyn/core/planning/lowest_first.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <random>
#include <vector>

using namespace marsyn::planning;

TEST(LowestFirst, LeavesOutOnlyWhatCannotBeTheMinimumOrNegative) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> value(-0.05, 1.0), gap(0.0, 0.3), tiny(0.0, 2e-3);
  int left_out_total = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 1 + trial % 60;
    std::vector<double> v(n), floor(n);
    const bool ties = trial % 3 == 0;  // values within a few thousandths of each other
    for (int i = 0; i < n; ++i) {
      v[i] = ties ? 0.2 + tiny(rng) : trial % 5 == 1 ? value(rng) + 0.1 : value(rng);
      floor[i] = v[i] - (ties ? tiny(rng) : gap(rng)) * (i % 4 == 0 ? 0.0 : 1.0);
    }
    const double known = trial % 7 == 0 ? 0.5 : std::numeric_limits<double>::infinity();
    const int threads = 1 + trial % 4;
    std::vector<std::atomic<int>> seen(n);
    const int checked = lowest_first(floor, known, threads, [&](int i, int worker) {
      EXPECT_GE(worker, 0);
      EXPECT_LT(worker, threads);
      ++seen[i];
      return v[i];
    });
    const double smallest = std::min(known, *std::min_element(v.begin(), v.end()));
    int count = 0;
    double found = known;
    for (int i = 0; i < n; ++i) {
      EXPECT_LE(seen[i].load(), 1) << trial;
      count += seen[i].load();
      if (seen[i].load()) {
        found = std::min(found, v[i]);
        continue;
      }
      ++left_out_total;
      EXPECT_TRUE(floor_decides(floor[i], smallest)) << "trial " << trial << " item " << i;
      EXPECT_GT(v[i], 0.0);
    }
    EXPECT_EQ(count, checked);
    EXPECT_EQ(found, smallest) << trial;
  }
  EXPECT_GT(left_out_total, 2000);  // the floors do leave items out
}

TEST(LowestFirst, NaNFloorsAndValuesAreChecked) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> floor{0.9, nan, 0.8, 0.95};
  std::vector<int> seen(4, 0);
  lowest_first(floor, std::numeric_limits<double>::infinity(), 1, [&](int i, int) {
    ++seen[i];
    return i == 2 ? nan : 1.0;  // a NaN value is the smallest: everything after it is left out
  });
  EXPECT_EQ(seen, (std::vector<int>{0, 1, 1, 0}));
}
