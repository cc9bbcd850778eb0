#pragma once
// Items with a cheap lower bound (a floor) and a costly value, of which only the smallest value
// and the negative ones matter: checked from the lowest floor up on several threads, and skipped
// once the floor shows the item can be neither (floor_decides against the smallest value found so
// far, which only falls). The continuous-time check's periods are such items: a period's floor
// comes from one enclosure of its whole flow, its value from the enclosures of its parts.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include "marsyn/core/parallel_tasks.hpp"

namespace marsyn::planning {

// floor_decides's allowance for rounding, relative to the margin: the floor and the values are
// computed on different boxes by the same evaluators, exactly ordered only up to rounding.
inline constexpr double kFloorSlack = 1e-9;

// True when every value at or above `floor` is positive and above `min_so_far`, by more than
// rounding: such a value can be neither a new minimum nor a shortfall.
inline bool floor_decides(double floor, double min_so_far) {
  const double slack = kFloorSlack * (1.0 + std::abs(floor));
  return floor > slack && floor > min_so_far + slack;
}

// Calls check(i, worker) for the items i whose value can matter and returns how many were
// checked; check returns item i's value (not below floor[i] but by rounding) and may use scratch
// of its worker (0 .. threads - 1). `bound`: a value already known to be an upper bound of the
// smallest (+inf if none). Every item left out satisfies floor_decides(floor[i], smallest value
// of all items and bound), whatever the number of threads; which of the others are checked as
// well depends on timing, so check must not depend on being called.
template <class Check>
int lowest_first(const std::vector<double>& floor, double bound, int threads, Check&& check) {
  const int n = static_cast<int>(floor.size());
  std::vector<int> order(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) order[i] = i;
  // NaN floors decide nothing: first, with -inf.
  auto key = [&](int i) { return std::isnan(floor[i]) ? -HUGE_VAL : floor[i]; };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
  std::atomic<int> next{0}, checked{0};
  std::atomic<double> low{bound};
  const int workers = std::clamp(threads, 1, std::max(1, n));
  parallel_tasks(workers, workers, [&](int worker) {
    for (int j = next++; j < n; j = next++) {
      const int i = order[j];
      // Floors only rise along the order and the bound only falls: once one decides, all later do.
      if (floor_decides(key(i), low.load())) return;
      const double v = check(i, worker);
      ++checked;
      for (double b = low.load(); !(v >= b) && !low.compare_exchange_weak(b, std::isnan(v) ? -HUGE_VAL : v);) {
      }
    }
  });
  return checked.load();
}

}  // namespace marsyn::planning
