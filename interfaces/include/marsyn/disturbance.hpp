#pragma once
// W(x, u) = w_base + sum_t gain_t |s_t| (TubeParams, docs/problem-format.md "disturbance"): the
// disturbance bound at one state and input, and an upper bound of it over boxes, rounded up,
// for trackers that enclose flows under it (docs/soundness.md section 12).
#include <algorithm>
#include <cmath>
#include <vector>

#include "marsyn/fast_interval.hpp"
#include "marsyn/problem.hpp"

namespace marsyn {

class DisturbanceBound {
 public:
  DisturbanceBound() = default;
  explicit DisturbanceBound(const TubeParams& t) : growth_(t.w_growth) {
    const Eigen::VectorXd& base = t.state_dependent() && t.w_base.size() == t.w.size() ? t.w_base : t.w;
    base_.assign(base.data(), base.data() + base.size());
  }
  // A constant bound (the tests' and the hand-written trackers' case).
  explicit DisturbanceBound(std::vector<double> w) : base_(std::move(w)) {}

  bool constant() const { return growth_.empty(); }
  int dim() const { return static_cast<int>(base_.size()); }
  const std::vector<double>& base() const { return base_; }
  const std::vector<DisturbanceGrowth>& growth() const { return growth_; }

  // W(x, u) at a point (simulation and sampling: ordinary rounding).
  void at(const double* x, const double* u, double* out) const {
    for (int i = 0; i < dim(); ++i) out[i] = base_[static_cast<std::size_t>(i)];
    for (const DisturbanceGrowth& g : growth_) {
      const double s = std::fabs(g.input ? u[g.index] : x[g.index]);
      for (int i = 0; i < dim(); ++i) out[i] += g.gain[i] * s;
    }
  }

  // A draw w made at W's largest value `top` (TubeParams::w), scaled coordinate by coordinate to
  // W(x, u) (a vertex stays a vertex; never beyond `top`). `scratch`: dim() numbers.
  void scale(const double* x, const double* u, const double* top, double* w, double* scratch) const {
    at(x, u, scratch);
    for (int i = 0; i < dim(); ++i) w[i] = top[i] > 0 ? w[i] * std::min(1.0, scratch[i] / top[i]) : 0.0;
  }

  // An upper bound of W over the boxes x (states) and u (inputs), every operation rounded up:
  // W_i(x', u') <= out[i] for every x' in x and u' in u.
  void sup(const FastInterval* x, const FastInterval* u, double* out) const {
    for (int i = 0; i < dim(); ++i) out[i] = base_[static_cast<std::size_t>(i)];
    for (const DisturbanceGrowth& g : growth_) {
      const double s = mag(g.input ? u[g.index] : x[g.index]);
      for (int i = 0; i < dim(); ++i)
        if (g.gain[i] != 0) out[i] = fast_detail::add_up(out[i], fast_detail::mul_up(g.gain[i], s));
    }
  }

 private:
  std::vector<double> base_;
  std::vector<DisturbanceGrowth> growth_;
};

}  // namespace marsyn
