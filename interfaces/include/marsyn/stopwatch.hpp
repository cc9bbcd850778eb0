#pragma once
// The one wall clock of the stages, the planners and the trackers (steady: it never jumps with
// the system clock). Started when made; a copy keeps the original's start, so a time limit can
// travel with the work it limits. Header-only so that core and plugins read one definition.
#include <chrono>

namespace marsyn {

class Stopwatch {
 public:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace marsyn
