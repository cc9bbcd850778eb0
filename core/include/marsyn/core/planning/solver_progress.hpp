#pragma once
// One planner solve as the user sees it (PlanSearchOptions::progress): iterations, cost and the
// last constraint violation the planner measured. A 100-agent plan runs for a minute: on a
// terminal (`live` set) a line redrawn in place at most ten times a second; otherwise a plain line
// through `log` at most every 10 s, so that a log file shows a long solve advancing and a short
// one says nothing.
#include <cstdio>
#include <functional>
#include <string>

#include "marsyn/planner.hpp"
#include "marsyn/stopwatch.hpp"

namespace marsyn::planning {

class SolverProgress {
 public:
  using Sink = std::function<void(const std::string&)>;
  SolverProgress(Sink log, Sink live) : log_(std::move(log)), live_(std::move(live)) {}

  // Called from the planner's own thread, one solve at a time.
  void operator()(const PlanProgress& p) {
    const double t = clock_.seconds();
    if (p.max_violation >= 0) violation_ = p.max_violation;  // planners report -1 between measurements
    if (t - drawn_ < (live_ ? 0.1 : 10.0)) return;
    drawn_ = t;
    const std::string line = "[plan] solving: iteration " + std::to_string(p.iteration) + ", cost " + short_number(p.cost) +
                             (violation_ >= 0 ? ", violation " + short_number(violation_) : "") + " after " +
                             std::to_string(static_cast<long>(t)) + " s";
    if (live_) live_(line);
    else if (log_) log_(line);
  }

 private:
  static std::string short_number(double v) {
    char s[32];
    std::snprintf(s, sizeof s, "%.4g", v);
    return s;
  }
  Sink log_, live_;
  Stopwatch clock_;
  double drawn_ = 0.0, violation_ = -1.0;
};

}  // namespace marsyn::planning
