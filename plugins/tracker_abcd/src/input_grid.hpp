#pragma once
// The finite input set: points lo + j * eta_u per dimension inside [lo, hi], numbered in mixed
// radix (first dimension slowest). Synthesis and the controller reader both decode an index
// with value(), so the applied input is bit-for-bit the one the abstraction was computed for.
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace marsyn::abcd {

class InputGrid {
 public:
  InputGrid() = default;
  InputGrid(std::vector<double> lo, std::vector<double> hi, std::vector<double> eta)
      : lo_(std::move(lo)), hi_(std::move(hi)), eta_(std::move(eta)) {
    if (lo_.size() != hi_.size() || lo_.size() != eta_.size() || lo_.empty())
      throw std::invalid_argument("input grid: bounds and eta_u must have the input dimension");
    total_ = 1;
    for (size_t j = 0; j < lo_.size(); ++j) {
      if (!(eta_[j] > 0) || !(hi_[j] >= lo_[j]) || !std::isfinite(hi_[j] - lo_[j]))
        throw std::invalid_argument("input grid: need lo <= hi and eta_u > 0");
      const double c = std::floor((hi_[j] - lo_[j]) / eta_[j] + 1e-9) + 1.0;
      if (c > 65000) throw std::invalid_argument("input grid: too many points");
      count_.push_back(static_cast<std::uint32_t>(c));
      total_ *= static_cast<std::int64_t>(c);
    }
  }
  int dim() const { return static_cast<int>(lo_.size()); }
  std::int64_t size() const { return total_; }
  const std::vector<double>& lo() const { return lo_; }
  const std::vector<double>& hi() const { return hi_; }
  const std::vector<double>& eta() const { return eta_; }
  const std::vector<std::uint32_t>& count() const { return count_; }

  // Grid points never leave U: the last point may exceed hi by rounding and is clamped.
  void value(std::int64_t index, double* u) const {
    for (int j = dim() - 1; j >= 0; --j) {
      const std::int64_t c = index % count_[j];
      index /= count_[j];
      u[j] = std::min(hi_[j], lo_[j] + static_cast<double>(c) * eta_[j]);
    }
  }

 private:
  std::vector<double> lo_, hi_, eta_;
  std::vector<std::uint32_t> count_;
  std::int64_t total_ = 0;
};

}  // namespace marsyn::abcd
