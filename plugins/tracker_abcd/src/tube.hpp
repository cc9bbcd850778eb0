#pragma once
// Tube cells per step and the winning set of a step with O(1) box-inclusion queries.
#include <cstdint>
#include <vector>

#include "marsyn/interval.hpp"
#include "uniform_grid.hpp"

namespace marsyn::abcd {

// Step k's tube: the cells lying entirely in [x_k - eps, x_k + eps] (rounding included). The
// bounds x_k -+ eps are enclosures of point-interval operations, which Boost's own mode-switching
// policy got wrong under GCC (docs/soundness.md, section 7); marsyn::Interval's policy is sound
// on them (interval.hpp), and tracker_abcd_test checks these bounds against 100 digits.
struct TubeBounds {
  Interval lo, hi;  // enclose x - eps and x + eps
};
inline TubeBounds tube_bounds(double x, double eps) { return {Interval(x) - Interval(eps), Interval(x) + Interval(eps)}; }

inline IndexBox tube_box(const UniformGrid& g, const double* xk, const double* eps) {
  IndexBox b;
  b.n = g.dim();
  for (int i = 0; i < b.n; ++i) {
    const TubeBounds t = tube_bounds(xk[i], eps[i]);
    g.inner_range(i, t.lo, t.hi, b.lo[i], b.hi[i]);
  }
  return b;
}

// Winning cells of one index box, with an n-dimensional prefix-sum table: "is every cell of
// this sub-box winning" costs 2^n lookups whatever the sub-box's size.
class WinningSet {
 public:
  WinningSet() = default;
  WinningSet(const IndexBox& box, const std::vector<std::uint8_t>& win) : box_(box), win_(win) {
    const int n = box.n;
    std::int64_t total = 1;
    for (int i = n - 1; i >= 0; --i) {
      stride_[i] = total;
      total *= box.extent(i) + 1;
    }
    sum_.assign(static_cast<size_t>(total), 0);
    // Fill P[a + 1] = win[a], then cumulate along each dimension.
    std::int64_t idx[kMaxDim];
    const std::int64_t cells = box.size();
    for (std::int64_t l = 0; l < cells; ++l) {
      if (!win[static_cast<size_t>(l)]) continue;
      box.unlinear(l, idx);
      std::int64_t p = 0;
      for (int i = 0; i < n; ++i) p += (idx[i] - box.lo[i] + 1) * stride_[i];
      sum_[static_cast<size_t>(p)] = 1;
    }
    for (int d = 0; d < n; ++d) {
      // Walk every position; add the predecessor along d.
      for (std::int64_t p = 0; p < total; ++p) {
        const std::int64_t coord = (p / stride_[d]) % (box.extent(d) + 1);
        if (coord > 0) sum_[static_cast<size_t>(p)] += sum_[static_cast<size_t>(p - stride_[d])];
      }
    }
  }
  const IndexBox& box() const { return box_; }

  // q must lie inside box().
  bool all_winning(const IndexBox& q) const {
    const int n = box_.n;
    bool single = true;
    for (int i = 0; i < n; ++i) single = single && q.lo[i] == q.hi[i];
    if (single) return win_[static_cast<size_t>(box_.linear(q.lo))] != 0;
    std::int64_t count = 0;
    for (unsigned mask = 0; mask < (1u << n); ++mask) {
      std::int64_t p = 0;
      int low = 0;
      for (int i = 0; i < n; ++i) {
        if (mask & (1u << i)) {
          p += (q.hi[i] - box_.lo[i] + 1) * stride_[i];
        } else {
          p += (q.lo[i] - box_.lo[i]) * stride_[i];
          ++low;
        }
      }
      count += (low & 1) ? -static_cast<std::int64_t>(sum_[static_cast<size_t>(p)]) : sum_[static_cast<size_t>(p)];
    }
    return count == q.size();
  }

 private:
  IndexBox box_;
  std::vector<std::uint8_t> win_;
  std::int64_t stride_[kMaxDim] = {};
  std::vector<std::int32_t> sum_;
};

}  // namespace marsyn::abcd
