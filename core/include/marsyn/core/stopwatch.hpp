#pragma once
// The wall clock core's stages time themselves with (steady: never jumps with the system
// clock). Started when made.
#include <chrono>

namespace marsyn {

class Stopwatch {
 public:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace marsyn
