// ChunkPool: the planners' fork-join on threads started once per solve. Every index is visited
// once, in the chunks the split promises; nested and concurrent calls run serially instead of
// deadlocking; the lowest failing chunk's exception comes back; the pool is reusable after one.
#include "marsyn/planner_support/chunk_pool.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

using marsyn::planner_support::ChunkPool;

namespace {

// The chunks of [0, n) a call on `chunks` threads must use.
std::vector<std::pair<int, int>> split(int n, int chunks) {
  std::vector<std::pair<int, int>> out;
  for (int c = 0; c < chunks; ++c)
    out.push_back({static_cast<int>(static_cast<long long>(n) * c / chunks),
                   static_cast<int>(static_cast<long long>(n) * (c + 1) / chunks)});
  return out;
}

}  // namespace

TEST(ChunkPool, EveryIndexOnceInThePromisedChunks) {
  for (int threads : {1, 2, 3, 5}) {
    ChunkPool pool(threads);
    EXPECT_EQ(pool.threads(), threads);
    for (int n : {0, 1, 2, 7, 100, 1001}) {
      for (int asked : {1, 2, 4, 9}) {
        const int chunks = std::max(1, std::min({asked, threads, n}));
        std::vector<std::atomic<int>> seen(static_cast<std::size_t>(n));
        std::vector<std::pair<int, int>> got(static_cast<std::size_t>(chunks), {-1, -1});
        std::vector<std::thread::id> who(static_cast<std::size_t>(chunks));
        pool.run(n, asked, [&](int c, int b, int e) {
          got[static_cast<std::size_t>(c)] = {b, e};
          who[static_cast<std::size_t>(c)] = std::this_thread::get_id();
          for (int i = b; i < e; ++i) seen[static_cast<std::size_t>(i)]++;
        });
        for (int i = 0; i < n; ++i) EXPECT_EQ(seen[static_cast<std::size_t>(i)].load(), 1) << n << " " << i;
        if (n > 0) {
          EXPECT_EQ(got, split(n, chunks)) << "n " << n << " asked " << asked << " threads " << threads;
          EXPECT_EQ(who[0], std::this_thread::get_id());  // the caller takes chunk 0
          for (int c = 1; c < chunks; ++c) EXPECT_NE(who[static_cast<std::size_t>(c)], who[0]);
        }
      }
    }
  }
}

// A chunk that calls the pool again gets its chunks run in its own thread, in order (the pool is
// busy with the outer call); another thread calling at the same time likewise. No deadlock.
TEST(ChunkPool, NestedAndConcurrentCallsRunSerially) {
  ChunkPool pool(2);
  std::vector<std::vector<int>> inner(2);
  pool.run(2, 2, [&](int c, int, int) {
    const auto me = std::this_thread::get_id();
    pool.run(6, 2, [&](int ic, int b, int e) {
      EXPECT_EQ(std::this_thread::get_id(), me);
      for (int i = b; i < e; ++i) inner[static_cast<std::size_t>(c)].push_back(i * 10 + ic);
    });
  });
  for (const auto& v : inner) EXPECT_EQ(v, (std::vector<int>{0, 10, 20, 31, 41, 51}));

  std::atomic<long> sum{0};
  auto many = [&] {
    for (int r = 0; r < 200; ++r)
      pool.run(64, 2, [&](int, int b, int e) {
        for (int i = b; i < e; ++i) sum += i;
      });
  };
  std::thread other(many);
  many();
  other.join();
  EXPECT_EQ(sum.load(), 2L * 200 * (63 * 64 / 2));
}

TEST(ChunkPool, TheLowestFailingChunksExceptionComesBackAndThePoolStaysUsable) {
  ChunkPool pool(3);
  try {
    pool.run(30, 3, [&](int c, int, int) {
      if (c >= 1) throw std::runtime_error("chunk " + std::to_string(c));
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "chunk 1");
  }
  std::atomic<int> count{0};
  pool.run(30, 3, [&](int, int b, int e) { count += e - b; });
  EXPECT_EQ(count.load(), 30);
  // The serial path (one thread asked) keeps the same rule.
  try {
    pool.run(30, 1, [&](int, int, int) { throw std::logic_error("serial"); });
    FAIL() << "no exception";
  } catch (const std::logic_error& e) {
    EXPECT_STREQ(e.what(), "serial");
  }
}
