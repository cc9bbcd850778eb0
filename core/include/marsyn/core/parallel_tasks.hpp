#pragma once
// Independent tasks 0..n-1 on up to `threads` threads, the calling thread among them, handed out
// one index at a time: their costs differ too much for fixed chunks (one agent's abstraction takes
// a minute, its neighbour's a second; a batch of kept runs is longer than a batch of plain ones).
// Returns when every task handed out has ended. A task that throws stops the handing out; the
// exception of the lowest failing index is rethrown, so the error reported does not depend on
// timing (every lower index was handed out before it and runs to its end).
#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace marsyn {

template <class F>
void parallel_tasks(int n, int threads, F&& task) {
  std::atomic<int> next{0};
  std::atomic<bool> stop{false};
  std::mutex error_mutex;
  int error_index = n;
  std::exception_ptr error;
  auto worker = [&] {
    while (!stop) {
      const int i = next++;  // once taken, an index runs: the lower ones of a failure all end
      if (i >= n) return;
      try {
        task(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (i < error_index) {
          error_index = i;
          error = std::current_exception();
        }
        stop = true;
      }
    }
  };
  const int pool_size = std::clamp(threads, 1, std::max(1, n)) - 1;
  std::vector<std::thread> pool;
  pool.reserve(static_cast<size_t>(pool_size));
  for (int t = 0; t < pool_size; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace marsyn
