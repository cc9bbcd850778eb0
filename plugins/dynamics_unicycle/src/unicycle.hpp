#pragma once
#include <algorithm>
#include <cmath>

#include "marsyn/dynamics.hpp"
#include "marsyn/params.hpp"

namespace marsyn::models {

// Unicycle (drones, lane-merging cars): x' = v cos(th), y' = v sin(th), th' = omega.
class Unicycle : public DynamicsModel<Unicycle> {
 public:
  explicit Unicycle(const Params& = {}) {}

  std::string type() const override { return "unicycle"; }
  int state_dim() const override { return 3; }
  int input_dim() const override { return 2; }
  std::vector<std::string> state_names() const override { return {"x", "y", "theta"}; }
  std::vector<std::string> input_names() const override { return {"v", "omega"}; }
  // Position never enters the field: successor boxes translate with the cell.
  std::vector<bool> field_independent_of() const override { return {true, true, false}; }
  std::vector<bool> periodic() const override { return {false, false, true}; }  // the heading

  template <class S>
  void vector_field(const S* x, const S* u, S* dx) const {
    using std::cos;
    using std::sin;
    // Both from one read of theta: after a store to dx the compiler must assume x changed (dx
    // may alias it) and would call sin and cos apart instead of one sincos.
    const S c = cos(x[2]), s = sin(x[2]);
    dx[0] = u[0] * c;
    dx[1] = u[0] * s;
    dx[2] = u[1];
  }
  // The verification's runs at once (Lanes::kWidth): sine and cosine from one argument
  // reduction (lanes.hpp), the values sin() and cos() give apart.
  void vector_field(const Lanes* x, const Lanes* u, Lanes* dx) const {
#ifdef MARSYN_LANES_VECTOR_MATH
    if (lanes_vector_math()) return field_avx2(x, u, dx);
#endif
    Lanes s, c;
    sincos(x[2], s, c);
    dx[0] = u[0] * c;
    dx[1] = u[0] * s;
    dx[2] = u[1];
  }
#ifdef MARSYN_LANES_VECTOR_MATH
  // The same values with the library's calls inline (lanes.hpp's wrappers are a call each, since a
  // function built for AVX2 cannot be inlined into one built without): the products are IEEE
  // per lane (-ffp-contract=off: not fused), as Lanes' operator* computes them.
  __attribute__((target("avx2,fma"))) static void field_avx2(const Lanes* x, const Lanes* u, Lanes* dx) {
    for (int i = 0; i < Lanes::kWidth; i += 4) {
      const __m256d th = _mm256_loadu_pd(x[2].v + i), v = _mm256_loadu_pd(u[0].v + i);
      _mm256_storeu_pd(dx[0].v + i, _mm256_mul_pd(v, lanes_detail::_ZGVdN4v_cos(th)));
      _mm256_storeu_pd(dx[1].v + i, _mm256_mul_pd(v, lanes_detail::_ZGVdN4v_sin(th)));
    }
    dx[2] = u[1];
  }
#endif
  // The planner's Jacobians evaluate this once per RK4 stage and agent: one sine and cosine and
  // no dual temporaries, with the arithmetic of the generic form above (same values bit for bit).
  void vector_field(const DualD* x, const DualD* u, DualD* dx) const {
    const double c = std::cos(x[2].v), s = std::sin(x[2].v), ms = -s;
    const int n = std::max(u[0].n, x[2].n);
    dx[0] = DualD(u[0].v * c);
    dx[1] = DualD(u[0].v * s);
    dx[0].n = dx[1].n = n;
    for (int i = 0; i < n; ++i) {
      const double du = u[0].derivative(i), dth = x[2].derivative(i);
      dx[0].d[i] = du * c + u[0].v * (ms * dth);
      dx[1].d[i] = du * s + u[0].v * (c * dth);
    }
    dx[2] = u[1];
  }
};

}  // namespace marsyn::models
