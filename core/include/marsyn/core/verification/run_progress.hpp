#pragma once
// The closed-loop runs as the user sees them (VerificationOptions::progress): runs done, runs per
// second and the time left. On a terminal (`live` set) a bar redrawn in place at most ten times
// a second; otherwise a plain line through `log` at every quarter, so that a log file stays short.
#include <cstdio>
#include <string>

#include "marsyn/core/progress_line.hpp"

namespace marsyn {

class RunProgress : public ProgressLine {
 public:
  RunProgress(Sink log, Sink live) : ProgressLine(std::move(log), std::move(live)) {}

  // verify() calls this under its own lock.
  void operator()(int done, int total) {
    const double t = seconds();
    char rate[96];
    std::snprintf(rate, sizeof rate, ", %.0f runs/s, about %.0f s left", t > 0 ? done / t : 0.0,
                  done > 0 ? t / done * (total - done) : 0.0);
    const std::string line = "[verify] " + std::to_string(done) + "/" + std::to_string(total) + " closed-loop runs" + rate;
    if (on_terminal()) return draw_bar(done, total, line, 0.1);
    const int quarter = total > 0 ? 4 * done / total : 4;
    if (quarter != last_quarter_) {
      last_quarter_ = quarter;
      log_now(line);
    }
  }

 private:
  int last_quarter_ = 0;
};

}  // namespace marsyn
