#pragma once
// One long agent's synthesis as the user sees it (TrackOptions::progress): "sweep step k of T"
// with an estimate of the time left from the steps so far. On a terminal (`live` set) a bar
// redrawn in place at every step; otherwise a plain line through `log` at most every 10 s and
// at the end, so that a log file shows a 50 s crane advancing.
#include <cstdio>
#include <mutex>
#include <string>

#include "marsyn/core/progress_line.hpp"

namespace marsyn {

class SweepProgress : public ProgressLine {
 public:
  SweepProgress(std::string what, Sink log, Sink live) : ProgressLine(std::move(log), std::move(live)), what_(std::move(what)) {}

  // Thread-safe: agents tracked side by side report from their own threads.
  void operator()(int done, int total) {
    const std::lock_guard<std::mutex> lock(m_);
    const double t = seconds();
    const double left = done > 0 ? t / done * (total - done) : 0.0;
    char eta[64];
    std::snprintf(eta, sizeof eta, "%.0f s, about %.0f s left", t, left);
    const std::string line = "[track] " + what_ + ": sweep step " + std::to_string(done) + " of " + std::to_string(total) +
                             " after " + eta;
    if (on_terminal()) draw_bar(done, total, line, 0.0);
    else log_every(line, 10.0, done >= total);
  }

 private:
  std::string what_;
  std::mutex m_;
};

}  // namespace marsyn
