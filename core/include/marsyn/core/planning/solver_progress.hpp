#pragma once
// One planner solve as the user sees it (PlanSearchOptions::progress): iterations, cost and the
// last constraint violation the planner measured. A 100-agent plan runs for a minute: on a
// terminal (`live` set) a line redrawn in place at most ten times a second; otherwise a plain line
// through `log` at most every 10 s, so that a log file shows a long solve advancing and a short
// one says nothing.
#include <cstdio>
#include <string>

#include "marsyn/core/progress_line.hpp"
#include "marsyn/planner.hpp"

namespace marsyn::planning {

class SolverProgress : public ProgressLine {
 public:
  SolverProgress(Sink log, Sink live) : ProgressLine(std::move(log), std::move(live)) {}

  // Called from the planner's own thread, one solve at a time.
  void operator()(const PlanProgress& p) {
    if (p.max_violation >= 0) violation_ = p.max_violation;  // planners report -1 between measurements
    const std::string line = "[plan] solving: iteration " + std::to_string(p.iteration) + ", cost " + short_number(p.cost) +
                             (violation_ >= 0 ? ", violation " + short_number(violation_) : "") + " after " +
                             std::to_string(static_cast<long>(seconds())) + " s";
    if (on_terminal()) draw(line, 0.1);
    else log_every(line, 10.0);
  }

 private:
  static std::string short_number(double v) {
    char s[32];
    std::snprintf(s, sizeof s, "%.4g", v);
    return s;
  }
  double violation_ = -1.0;
};

}  // namespace marsyn::planning
