#pragma once
// The wall clock every planner measures its solve time and time limit with (seconds, steady:
// never jumps with the system clock).
#include <chrono>

namespace marsyn::planner_support {

inline double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace marsyn::planner_support
