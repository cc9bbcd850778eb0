#pragma once
// The state grid: cells of size eta aligned at a global origin, addressed by 64-bit indices, and
// boxes of cell indices (a step's tube, a successor's cover). Nothing here allocates per cell.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "marsyn/interval.hpp"

namespace marsyn::abcd {

inline constexpr int kMaxDim = 8;

// Closed box of cell indices [lo, hi] per dimension, row-major with the last dimension fastest.
struct IndexBox {
  int n = 0;
  std::int64_t lo[kMaxDim] = {}, hi[kMaxDim] = {};

  bool empty() const {
    for (int i = 0; i < n; ++i)
      if (lo[i] > hi[i]) return true;
    return false;
  }
  std::int64_t extent(int i) const { return hi[i] - lo[i] + 1; }
  std::int64_t size() const {
    if (empty()) return 0;
    std::int64_t s = 1;
    for (int i = 0; i < n; ++i) s *= extent(i);
    return s;
  }
  bool contains(const std::int64_t* idx) const {
    for (int i = 0; i < n; ++i)
      if (idx[i] < lo[i] || idx[i] > hi[i]) return false;
    return true;
  }
  bool contains(const IndexBox& b) const {
    for (int i = 0; i < n; ++i)
      if (b.lo[i] < lo[i] || b.hi[i] > hi[i]) return false;
    return true;
  }
  std::int64_t linear(const std::int64_t* idx) const {
    std::int64_t l = 0;
    for (int i = 0; i < n; ++i) l = l * extent(i) + (idx[i] - lo[i]);
    return l;
  }
  void unlinear(std::int64_t l, std::int64_t* idx) const {
    for (int i = n - 1; i >= 0; --i) {
      const std::int64_t e = extent(i);
      idx[i] = lo[i] + l % e;
      l /= e;
    }
  }
};

class UniformGrid {
 public:
  UniformGrid() = default;
  UniformGrid(std::vector<double> origin, std::vector<double> eta) : origin_(std::move(origin)), eta_(std::move(eta)) {
    if (origin_.size() != eta_.size() || origin_.empty() || origin_.size() > static_cast<size_t>(kMaxDim))
      throw std::invalid_argument("grid: dimension must be 1.." + std::to_string(kMaxDim));
    for (double e : eta_)
      if (!(e > 0) || !std::isfinite(e)) throw std::invalid_argument("grid: eta must be positive");
  }
  int dim() const { return static_cast<int>(eta_.size()); }
  const std::vector<double>& origin() const { return origin_; }
  const std::vector<double>& eta() const { return eta_; }

  // The quantizer the controller uses. It is monotone in x (rounded subtraction and division by
  // a positive number and floor are all monotone), which makes the cover of a box [a, b] exactly
  // the index range [index(a), index(b)].
  std::int64_t index(int i, double x) const { return static_cast<std::int64_t>(std::floor((x - origin_[i]) / eta_[i])); }

  // Encloses every real x whose double representation quantizes to idx: the computed quotient
  // (x - o) / eta carries a relative error of a few ulps plus |o| ulps from representing x, so
  // the preimage of idx is [idx, idx + 1] cells widened by a slack far above that error.
  Interval cell(int i, std::int64_t idx) const {
    const double slack = 1e-12 * (static_cast<double>(std::llabs(idx)) + 2.0 + std::abs(origin_[i]) / eta_[i]);
    return Interval(origin_[i]) +
           (Interval(static_cast<double>(idx)) + Interval(-slack, 1.0 + slack)) * Interval(eta_[i]);
  }

  // Cells whose whole enclosure lies in [lo, hi] (the tube: "entirely inside the eps box").
  // lo and hi are given as intervals so that callers can pass x_k -/+ eps with its rounding.
  void inner_range(int i, const Interval& lo, const Interval& hi, std::int64_t& first, std::int64_t& last) const {
    first = static_cast<std::int64_t>(std::floor((lo.upper() - origin_[i]) / eta_[i])) - 1;
    while (cell(i, first).lower() < lo.upper()) ++first;
    last = static_cast<std::int64_t>(std::floor((hi.lower() - origin_[i]) / eta_[i])) + 1;
    while (cell(i, last).upper() > hi.lower()) --last;
  }

 private:
  std::vector<double> origin_, eta_;
};

}  // namespace marsyn::abcd
