#include "marsyn/planner_support/chunk_pool.hpp"

#include <algorithm>

namespace marsyn::planner_support {

namespace {

int edge(int n, int chunks, int c) { return static_cast<int>(static_cast<long long>(n) * c / chunks); }

// The pool whose chunk this thread is running (its workers always): a call from inside must not
// wait for the pool it is part of (nor try to lock a mutex its own thread holds).
thread_local const ChunkPool* inside = nullptr;

}  // namespace

ChunkPool::ChunkPool(int threads) {
  const int workers = std::max(0, threads - 1);
  errors_.resize(static_cast<std::size_t>(workers) + 1);
  workers_.reserve(static_cast<std::size_t>(workers));
  for (int id = 0; id < workers; ++id) workers_.emplace_back([this, id] { work(id); });
}

ChunkPool::~ChunkPool() {
  {
    const std::lock_guard<std::mutex> lock(m_);
    quit_ = true;
  }
  wake_.notify_all();
  for (auto& t : workers_) t.join();
}

void ChunkPool::dispatch(int n, int threads, Call call, void* ctx) {
  const int chunks = std::max(1, std::min({threads, this->threads(), n}));
  std::unique_lock<std::mutex> busy(busy_, std::defer_lock);
  if (chunks == 1 || inside == this || !busy.try_lock()) {
    // Serial: the same chunks in order (a nested or concurrent call, or one thread).
    std::exception_ptr first;
    for (int c = 0; c < chunks && n > 0; ++c) {
      try {
        call(ctx, c, edge(n, chunks, c), edge(n, chunks, c + 1));
      } catch (...) {
        if (!first) first = std::current_exception();
      }
    }
    if (first) std::rethrow_exception(first);
    return;
  }
  {
    const std::lock_guard<std::mutex> lock(m_);
    call_ = call;
    ctx_ = ctx;
    n_ = n;
    chunks_ = chunks;
    pending_ = chunks - 1;
    std::fill(errors_.begin(), errors_.end(), nullptr);
    ++generation_;
  }
  wake_.notify_all();
  inside = this;
  try {
    call(ctx, 0, 0, edge(n, chunks, 1));
  } catch (...) {
    errors_[0] = std::current_exception();
  }
  inside = nullptr;
  std::unique_lock<std::mutex> lock(m_);
  done_.wait(lock, [&] { return pending_ == 0; });
  call_ = nullptr;
  for (const auto& e : errors_)
    if (e) std::rethrow_exception(e);
}

void ChunkPool::work(int id) {
  const int chunk = id + 1;
  inside = this;
  unsigned long seen = 0;
  std::unique_lock<std::mutex> lock(m_);
  for (;;) {
    wake_.wait(lock, [&] { return quit_ || generation_ != seen; });
    if (quit_) return;
    seen = generation_;
    if (chunk >= chunks_) continue;  // this call uses fewer chunks than the pool has threads
    const Call call = call_;
    void* ctx = ctx_;
    const int begin = edge(n_, chunks_, chunk), end = edge(n_, chunks_, chunk + 1);
    lock.unlock();
    std::exception_ptr error;
    try {
      call(ctx, chunk, begin, end);
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    errors_[static_cast<std::size_t>(chunk)] = error;
    if (--pending_ == 0) done_.notify_one();
  }
}

}  // namespace marsyn::planner_support
