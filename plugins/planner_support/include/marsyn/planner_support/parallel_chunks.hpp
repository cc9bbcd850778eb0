#pragma once
// Fork-join over an index range for the planners' per-knot and per-agent loops. Threads are
// started per call: the loops this serves take milliseconds (a team's Jacobians over the horizon),
// against tens of microseconds to start a thread, and a pool would outlive the plugin's solve().
// Results must not depend on the split: callers write per-index outputs and reduce them in
// index order, so a plan is the same bit for bit with any number of threads.
#include <algorithm>
#include <exception>
#include <thread>
#include <vector>

namespace marsyn::planner_support {

// f(chunk, begin, end) on contiguous chunks of [0, n), at most `threads` of them, the calling
// thread taking chunk 0; returns when every chunk is done and rethrows the first exception.
template <class F>
void parallel_chunks(int n, int threads, F&& f) {
  threads = std::max(1, std::min(threads, n));
  if (threads == 1) {
    if (n > 0) f(0, 0, n);
    return;
  }
  auto edge = [&](int c) { return static_cast<int>(static_cast<long long>(n) * c / threads); };
  std::vector<std::exception_ptr> error(threads);
  std::vector<std::thread> pool;
  pool.reserve(threads - 1);
  for (int c = 1; c < threads; ++c)
    pool.emplace_back([&, c] {
      try {
        f(c, edge(c), edge(c + 1));
      } catch (...) {
        error[c] = std::current_exception();
      }
    });
  try {
    f(0, 0, edge(1));
  } catch (...) {
    error[0] = std::current_exception();
  }
  for (auto& t : pool) t.join();
  for (auto& e : error)
    if (e) std::rethrow_exception(e);
}

// Threads for a solver: `requested` (0: the machine's, at most 8).
inline int solver_threads(int requested) {
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return static_cast<int>(std::clamp(hw, 1u, 8u));
}

}  // namespace marsyn::planner_support
