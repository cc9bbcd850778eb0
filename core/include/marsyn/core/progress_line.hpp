#pragma once
// What the progress lines of the plan, track and verify stages share: a terminal line redrawn in
// place (`live`, set only when stderr is a terminal) or plain lines appended to a log (`log`), a
// clock, and throttles that keep a terminal at a few redraws a second and a log file short. Each
// stage's class keeps only its own text and its own rule for when to speak.
#include <algorithm>
#include <functional>
#include <string>

#include "marsyn/stopwatch.hpp"

namespace marsyn {

class ProgressLine {
 public:
  using Sink = std::function<void(const std::string&)>;

 protected:
  ProgressLine(Sink log, Sink live) : log_(std::move(log)), live_(std::move(live)) {}

  bool on_terminal() const { return static_cast<bool>(live_); }
  double seconds() const { return clock_.seconds(); }

  // Redraws the terminal line with a bar of done/total in front unless the last redraw was less
  // than `every` seconds ago; the last one (done >= total) always, and it ends the line.
  void draw_bar(int done, int total, const std::string& text, double every) {
    const double t = seconds();
    const bool last = done >= total;
    if (!last && t - drawn_ < every) return;
    drawn_ = t;
    const int width = 30, filled = total > 0 ? width * std::min(done, total) / total : width;
    live_("[" + std::string(static_cast<size_t>(filled), '#') + std::string(static_cast<size_t>(width - filled), '.') +
          "] " + text);
    if (last) live_("");
  }
  // The terminal line without a bar, at most once per `every` seconds.
  void draw(const std::string& text, double every) {
    const double t = seconds();
    if (t - drawn_ < every) return;
    drawn_ = t;
    live_(text);
  }
  // A log line, at most once per `every` seconds (the first after `every`); `last` adds the
  // closing line, but only after earlier ones: a short stage says nothing.
  void log_every(const std::string& text, double every, bool last = false) {
    if (!log_) return;
    const double t = seconds();
    if (t - logged_ >= every || (last && logged_any_)) {
      logged_ = t;
      logged_any_ = true;
      log_(text);
    }
  }
  void log_now(const std::string& text) {
    if (log_) log_(text);
  }

 private:
  Sink log_, live_;
  Stopwatch clock_;
  double drawn_ = 0.0, logged_ = 0.0;  // the first line after `every`: a short stage draws little
  bool logged_any_ = false;
};

}  // namespace marsyn
