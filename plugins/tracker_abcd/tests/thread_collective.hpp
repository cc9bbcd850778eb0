#pragma once
// A Collective over threads of one process, for testing a split sweep without MPI: R threads
// play the R ranks, meeting at a barrier for every exchange.
#include <barrier>
#include <cstdint>
#include <memory>
#include <vector>

#include "marsyn/collective.hpp"

namespace marsyn::abcd::testing {

class ThreadGroup {
 public:
  explicit ThreadGroup(int ranks) : slots_(static_cast<size_t>(ranks)), barrier_(ranks) {}
  int size() const { return static_cast<int>(slots_.size()); }

  std::vector<std::vector<std::uint8_t>> allgather(int rank, const std::vector<std::uint8_t>& mine) {
    slots_[static_cast<size_t>(rank)] = mine;
    barrier_.arrive_and_wait();  // every slot written
    auto all = slots_;
    barrier_.arrive_and_wait();  // every slot read before the next exchange overwrites it
    return all;
  }
  void broadcast(int rank, std::vector<std::uint8_t>& bytes, int root) {
    if (rank == root) slots_[0] = bytes;
    barrier_.arrive_and_wait();
    if (rank != root) bytes = slots_[0];
    barrier_.arrive_and_wait();
  }

 private:
  std::vector<std::vector<std::uint8_t>> slots_;
  std::barrier<> barrier_;
};

class ThreadCollective final : public Collective {
 public:
  ThreadCollective(ThreadGroup& g, int rank) : g_(g), rank_(rank) {}
  int rank() const override { return rank_; }
  int size() const override { return g_.size(); }
  std::vector<std::vector<std::uint8_t>> allgather(const std::vector<std::uint8_t>& mine) const override {
    return g_.allgather(rank_, mine);
  }
  void broadcast(std::vector<std::uint8_t>& bytes, int root) const override { g_.broadcast(rank_, bytes, root); }

 private:
  ThreadGroup& g_;
  int rank_;
};

}  // namespace marsyn::abcd::testing
