#pragma once
// The closed-loop runs' integrator: one RK4 substep of one agent for Lanes::kWidth runs at once,
// lane by lane the arithmetic of rk4_step_lanes(f, x, u, w, tau, substeps, out, 1) bit for bit
// (LanesRk4 in tests/core/lanes_test.cpp), with two savings that cannot change a bit:
// - the stage arithmetic on packed vectors (GCC vector extensions: a packed add or multiply rounds
//   each lane as the scalar operation does; the interfaces' -ffp-contract=off keeps them from
//   fusing), where rk4_detail's generic code goes through Lanes' lane loops;
// - the field's value at stage 3 taken from stage 2 when every column the field reads
//   (Dynamics::field_independent_of) holds the same bits in both stage points, in every lane: a
//   field is a function of those columns and the input, so it would give the same bits. A
//   unicycle's heading rate is its input plus the disturbance, so stages 2 and 3 see the same
//   heading and one of its four sine-cosine evaluations per substep goes.
#include <cstring>
#include <vector>

#include "marsyn/dynamics.hpp"
#include "marsyn/lanes.hpp"

namespace marsyn::verification_detail {

class LanesRk4 {
 public:
  explicit LanesRk4(const Dynamics& f) : f_(f), n_(f.state_dim()) {
    const std::vector<bool> free = f.field_independent_of();
    for (int c = 0; c < n_; ++c)
      if (c >= static_cast<int>(free.size()) || !free[static_cast<size_t>(c)]) reads_.push_back(c);
    scratch_.resize(static_cast<size_t>(5 * n_));
  }

  // out = x after one substep h = tau / substeps under u and w (per lane); out may not alias x.
  void step(const Lanes* x, const Lanes* u, const Lanes* w, double tau, int substeps, Lanes* out) {
    // The common state sizes with their loops unrolled (the same operations in the same order).
    switch (n_) {
      case 3: return step_n<3>(x, u, w, tau, substeps, out);
      case 4: return step_n<4>(x, u, w, tau, substeps, out);
      case 6: return step_n<6>(x, u, w, tau, substeps, out);
      default: return step_n<0>(x, u, w, tau, substeps, out);
    }
  }

  // Whether some step so far took stage 3's field from stage 2 (for the tests).
  bool reuses_stage_two() const { return reused_; }

 private:
  // N > 0: n_ == N known at compile time; N == 0: any n_.
  template <int N>
  void step_n(const Lanes* x, const Lanes* u, const Lanes* w, double tau, int substeps, Lanes* out) {
    // Two doubles per vector: SSE2's width, which every x86-64 has (a 32-byte vector would pass
    // through memory without AVX); the compiler unrolls the two halves.
    using V = double __attribute__((vector_size(2 * sizeof(double))));
    static_assert(Lanes::kWidth % 2 == 0);
    constexpr int kHalves = Lanes::kWidth / 2;
    auto at = [](const Lanes& a, int j) {
      V v;
      std::memcpy(&v, a.v + 2 * j, sizeof v);
      return v;
    };
    auto put = [](Lanes& a, int j, V v) { std::memcpy(a.v + 2 * j, &v, sizeof v); };
    const int n = N > 0 ? N : n_;
    Lanes *k1 = scratch_.data(), *k2 = k1 + n, *k3 = k2 + n, *k4 = k3 + n, *y = k4 + n;
    const double h = tau / substeps;
    const V half = V{} + 0.5 * h, full = V{} + h, sixth = V{} + h / 6.0, two = V{} + 2.0;
    auto rhs = [&](const Lanes* state, Lanes* d) {
      f_.field(state, u, d);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < kHalves; ++j) put(d[i], j, at(d[i], j) + at(w[i], j));
    };
    // y = x + c k, the stage point.
    auto point = [&](V c, const Lanes* k) {
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < kHalves; ++j) put(y[i], j, at(x[i], j) + c * at(k[i], j));
    };
    rhs(x, k1);
    point(half, k1);
    rhs(y, k2);
    // Stage 3's point against stage 2's, in the columns the field reads.
    bool same = true;
    for (int c : reads_)
      for (int j = 0; j < kHalves; ++j) {
        const V next = at(x[c], j) + half * at(k2[c], j);
        same = same && std::memcmp(&next, y[c].v + 2 * j, sizeof next) == 0;
      }
    if (same) {
      reused_ = true;
      for (int i = 0; i < n; ++i) k3[i] = k2[i];
    } else {
      point(half, k2);
      rhs(y, k3);
    }
    point(full, k3);
    rhs(y, k4);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < kHalves; ++j)
        put(out[i], j, at(x[i], j) + sixth * (at(k1[i], j) + two * at(k2[i], j) + two * at(k3[i], j) + at(k4[i], j)));
  }

  const Dynamics& f_;
  int n_;
  std::vector<int> reads_;      // the state columns the field reads
  std::vector<Lanes> scratch_;  // k1..k4 and the stage point: nothing allocated per step
  bool reused_ = false;
};

}  // namespace marsyn::verification_detail
