#pragma once
// Fork-join over an index range for the planners' per-knot and per-agent loops, on threads started
// once per solve. A solver's per-iteration loops (Jacobians, expansion, rollouts) take a few
// hundred microseconds on a small team, about what starting and joining a thread costs: with
// threads started per loop, two threads planned the ten drones no faster than one. The pool
// belongs to one solve (a member of the solver), so no thread outlives the plugin that started it.
//
// Chunk c of `chunks` covers [n c / chunks, n (c + 1) / chunks) and the calling thread takes
// chunk 0. Results must not depend on the split: callers write per-index outputs and reduce them
// in index order, so a plan is the same bit for bit with any number of threads. A call made while
// the pool is busy (from one of its own chunks, or from another thread) runs its chunks in the
// calling thread, in order.
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

namespace marsyn::planner_support {

class ChunkPool {
 public:
  // `threads` - 1 workers (none for threads <= 1).
  explicit ChunkPool(int threads);
  ~ChunkPool();
  ChunkPool(const ChunkPool&) = delete;
  ChunkPool& operator=(const ChunkPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }

  // f(chunk, begin, end) on at most min(threads, this pool's threads, n) chunks of [0, n);
  // returns when every chunk is done and rethrows the exception of the lowest failing chunk.
  template <class F>
  void run(int n, int threads, F&& f) {
    auto call = [](void* ctx, int c, int b, int e) { (*static_cast<std::remove_reference_t<F>*>(ctx))(c, b, e); };
    dispatch(n, threads, call, const_cast<void*>(static_cast<const void*>(&f)));
  }

 private:
  using Call = void (*)(void*, int, int, int);
  void dispatch(int n, int threads, Call call, void* ctx);
  void work(int id);

  std::vector<std::thread> workers_;
  std::mutex busy_;  // held by the thread whose call the workers serve
  std::mutex m_;
  std::condition_variable wake_, done_;
  // The current call, read by the workers under m_.
  Call call_ = nullptr;
  void* ctx_ = nullptr;
  int n_ = 0, chunks_ = 0, pending_ = 0;
  unsigned long generation_ = 0;
  bool quit_ = false;
  std::vector<std::exception_ptr> errors_;
};

// Threads for a solver: `requested` (0: the machine's, at most 8).
inline int solver_threads(int requested) {
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return static_cast<int>(hw < 1u ? 1u : hw > 8u ? 8u : hw);
}

}  // namespace marsyn::planner_support
