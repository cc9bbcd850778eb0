#pragma once
// One long agent's synthesis as the user sees it (TrackOptions::progress): "sweep step k of T"
// with an estimate of the time left from the steps so far. On a terminal (`live` set) a bar
// redrawn in place at every step; otherwise a plain line through `log` at most every 10 s and
// at the end, so that a log file shows a 50 s crane advancing.
#include <cstdio>
#include <functional>
#include <mutex>
#include <string>

#include "marsyn/stopwatch.hpp"

namespace marsyn {

class SweepProgress {
 public:
  using Sink = std::function<void(const std::string&)>;
  SweepProgress(std::string what, Sink log, Sink live) : what_(std::move(what)), log_(std::move(log)), live_(std::move(live)) {}

  // Thread-safe: agents tracked side by side report from their own threads.
  void operator()(int done, int total) {
    const std::lock_guard<std::mutex> lock(m_);
    const double t = clock_.seconds();
    const double left = done > 0 ? t / done * (total - done) : 0.0;
    char eta[64];
    std::snprintf(eta, sizeof eta, "%.0f s, about %.0f s left", t, left);
    const std::string line = "[track] " + what_ + ": sweep step " + std::to_string(done) + " of " + std::to_string(total) +
                             " after " + eta;
    if (live_) {
      const int width = 30, filled = total > 0 ? width * done / total : width;
      live_("[" + std::string(static_cast<size_t>(filled), '#') + std::string(static_cast<size_t>(width - filled), '.') +
            "] " + line);
      if (done >= total) live_("");
      return;
    }
    // The last step only after earlier lines: a short agent says nothing here.
    if (log_ && (t - last_ >= 10.0 || (done >= total && printed_))) {
      last_ = t;
      printed_ = true;
      log_(line);
    }
  }

 private:
  std::string what_;
  Sink log_, live_;
  Stopwatch clock_;
  double last_ = 0.0;
  bool printed_ = false;
  std::mutex m_;
};

}  // namespace marsyn
