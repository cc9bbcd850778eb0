#pragma once
// The closed-loop runs as the user sees them (VerificationOptions::progress): runs done, runs per
// second and the time left. On a terminal (`live` set) a bar redrawn in place at most ten times
// a second; otherwise a plain line through `log` at every quarter, so that a log file stays short.
#include <cstdio>
#include <functional>
#include <string>

#include "marsyn/stopwatch.hpp"

namespace marsyn {

class RunProgress {
 public:
  using Sink = std::function<void(const std::string&)>;
  RunProgress(Sink log, Sink live) : log_(std::move(log)), live_(std::move(live)) {}

  // verify() calls this under its own lock.
  void operator()(int done, int total) {
    const double t = clock_.seconds();
    char rate[96];
    std::snprintf(rate, sizeof rate, ", %.0f runs/s, about %.0f s left", t > 0 ? done / t : 0.0,
                  done > 0 ? t / done * (total - done) : 0.0);
    const std::string line = "[verify] " + std::to_string(done) + "/" + std::to_string(total) + " closed-loop runs" + rate;
    if (live_) {
      if (done < total && t - drawn_ < 0.1) return;  // a terminal needs no more than ten redraws a second
      drawn_ = t;
      const int width = 30, filled = total > 0 ? width * done / total : width;
      live_("[" + std::string(static_cast<size_t>(filled), '#') + std::string(static_cast<size_t>(width - filled), '.') +
            "] " + line);
      if (done >= total) live_("");
      return;
    }
    const int quarter = total > 0 ? 4 * done / total : 4;
    if (log_ && quarter != last_quarter_) {
      last_quarter_ = quarter;
      log_(line);
    }
  }

 private:
  Sink log_, live_;
  Stopwatch clock_;
  int last_quarter_ = 0;
  double drawn_ = -1.0;
};

}  // namespace marsyn
