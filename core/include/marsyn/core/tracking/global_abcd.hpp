#pragma once
// The global ABCD baseline of the paper's Table 2: one abstraction of the product system over
// its whole domain with a time-invariant reach-avoid controller, attempted only when its size
// fits a memory budget.
#include <functional>
#include <string>

#include "marsyn/problem.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn {

// True when the product cell [lo, hi] may meet the avoid set: interval workspace boxes of every
// agent against each obstacle's bounding box and against each other, in the problem's norm.
// An over-approximation, as a sound controller needs. Formation constraints are not supported.
std::function<bool(const double*, const double*)> product_unsafe(const Problem& problem);

struct GlobalAbcdRun {
  std::string status;  // "controller: x0 winning" / "no controller: ..." / tracker status
  double time_s = 0;
  long long boxes_computed = 0;
  bool initial_state_winning = false;
};

GlobalAbcdRun run_global_abcd(const Problem& problem, const Tracker& tracker, int threads, double memory_budget_bytes);

}  // namespace marsyn
