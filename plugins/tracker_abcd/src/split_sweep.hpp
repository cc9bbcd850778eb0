#pragma once
// One agent's backward sweep shared by several ranks (docs/mpi.md, "One heavy agent"): each
// step's columns (cells with the same indices along the coordinates the field reads) are dealt
// to ranks by a function of their absolute indices, so a column keeps its rank, and its cached
// successor boxes, from one step to the next. After step k every rank knows the inputs of its
// own cells only; the winning set of step k, which step k - 1 reads, is exchanged as one bit per
// cell (allgather). The inputs themselves are exchanged once, after the sweep. A cell's input
// is the first input in the step's order whose box is inside the winning set of step k + 1: a
// function of the cell and that set only, so the result does not depend on the number of ranks
// or threads.
#include <cstdint>
#include <vector>

#include "marsyn/collective.hpp"
#include "uniform_grid.hpp"

namespace marsyn::abcd {

class SweepSplit {
 public:
  SweepSplit(const Collective* c, int threads, const std::vector<bool>& invariant)
      : c_(c), ranks_(c ? c->size() : 1), rank_(c ? c->rank() : 0), threads_(threads < 1 ? 1 : threads), inv_(invariant) {}

  bool split() const { return ranks_ > 1; }
  int ranks() const { return ranks_; }
  // Whether thread t of this rank owns the column of cell index idx. The sum of the indices the
  // field reads alternates between neighbouring columns, which balances the load: its residue
  // picks the rank, the quotient the thread (one rank: the residue modulo the threads).
  bool owns(const std::int64_t* idx, int t) const {
    const std::int64_t s = column_sum(idx);
    if (mod(s, ranks_) != rank_) return false;
    return threads_ <= 1 || mod(floor_div(s, ranks_), threads_) == t;
  }
  int rank_of(const std::int64_t* idx) const { return static_cast<int>(mod(column_sum(idx), ranks_)); }

  // Step k's winning set `win` (one byte per cell of bk), from this rank's inputs of the step
  // (`inputs`, kLosing where not won or not owned) and the other ranks' bits. Returns the bytes
  // this rank sent (for the communication figures).
  std::int64_t exchange_winning(const IndexBox& bk, const std::uint16_t* inputs, std::uint16_t losing,
                                std::vector<std::uint8_t>& win) const;
  // After the sweep: every rank's inputs of its own cells for steps [first, last], in place.
  std::int64_t exchange_inputs(const std::vector<IndexBox>& boxes, const std::vector<std::int64_t>& offsets, int first,
                               int last, std::vector<std::uint16_t>& inputs) const;
  long long sum(long long mine) const;

 private:
  std::int64_t column_sum(const std::int64_t* idx) const {
    std::int64_t s = 0;
    for (size_t i = 0; i < inv_.size(); ++i)
      if (!inv_[i]) s += idx[i];
    return s;
  }
  static std::int64_t mod(std::int64_t a, std::int64_t b) {
    const std::int64_t r = a % b;
    return r < 0 ? r + b : r;
  }
  static std::int64_t floor_div(std::int64_t a, std::int64_t b) { return (a - mod(a, b)) / b; }
  // Calls fn(l) for every cell l of b owned by rank q, in increasing l.
  template <class Fn>
  void cells_of(const IndexBox& b, int q, Fn fn) const {
    std::int64_t idx[kMaxDim];
    const std::int64_t cells = b.size();
    for (std::int64_t l = 0; l < cells; ++l) {
      b.unlinear(l, idx);
      if (rank_of(idx) == q) fn(l);
    }
  }

  const Collective* c_;
  int ranks_, rank_, threads_;
  std::vector<bool> inv_;
};

}  // namespace marsyn::abcd
