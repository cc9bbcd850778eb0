#pragma once
// The closed-loop runs' integrator: one RK4 substep of one agent for Lanes::kWidth runs at once,
// lane by lane the arithmetic of rk4_step_lanes(f, x, u, w, tau, substeps, out, 1) bit for bit
// (LanesRk4 in tests/core/lanes_test.cpp), with two savings that cannot change a bit:
// - the stage arithmetic on packed vectors (GCC vector extensions: a packed add or multiply rounds
//   each lane as the scalar operation does; the interfaces' -ffp-contract=off keeps them from
//   fusing), where rk4_detail's generic code goes through Lanes' lane loops: the four lanes in one
//   AVX2 vector where the CPU has AVX2 (chosen at run time), two SSE2 vectors otherwise;
// - the field's value at stage 3 taken from stage 2 when every column the field reads
//   (Dynamics::field_independent_of) holds the same bits in both stage points, in every lane: a
//   field is a function of those columns and the input, so it would give the same bits. A
//   unicycle's heading rate is its input plus the disturbance, so stages 2 and 3 see the same
//   heading and one of its four sine-cosine evaluations per substep goes.
#include <cstring>
#include <type_traits>
#include <vector>

#include "marsyn/dynamics.hpp"
#include "marsyn/lanes.hpp"

namespace marsyn::verification_detail {

// (The 32-byte type is only used inside functions built for AVX2, where it stays in registers;
// GCC still warns of its by-value ABI in the always-inline helpers.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
using Double2 = double __attribute__((vector_size(2 * sizeof(double))));
using Double4 = double __attribute__((vector_size(4 * sizeof(double))));

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
#if defined(__x86_64__) && defined(__GNUC__)
    if (avx_) {
      switch (n_) {
        case 3: return step_avx<3>(x, u, w, tau, substeps, out);
        case 4: return step_avx<4>(x, u, w, tau, substeps, out);
        case 6: return step_avx<6>(x, u, w, tau, substeps, out);
        default: return step_avx<0>(x, u, w, tau, substeps, out);
      }
    }
#endif
    // The common state sizes with their loops unrolled (the same operations in the same order).
    switch (n_) {
      case 3: return step_n<3, 2>(x, u, w, tau, substeps, out);
      case 4: return step_n<4, 2>(x, u, w, tau, substeps, out);
      case 6: return step_n<6, 2>(x, u, w, tau, substeps, out);
      default: return step_n<0, 2>(x, u, w, tau, substeps, out);
    }
  }

  // Whether some step so far took stage 3's field from stage 2 (for the tests).
  bool reuses_stage_two() const { return reused_; }

 private:
#if defined(__x86_64__) && defined(__GNUC__)
  // All four lanes in one 256-bit vector where the CPU has AVX2 (the same per-lane IEEE adds and
  // multiplies, unfused: -ffp-contract=off, and no FMA in the target): half the instructions.
  template <int N>
  __attribute__((target("avx2"))) void step_avx(const Lanes* x, const Lanes* u, const Lanes* w, double tau,
                                                int substeps, Lanes* out) {
    step_n<N, 4>(x, u, w, tau, substeps, out);
  }
#endif

  // N > 0: n_ == N known at compile time; N == 0: any n_. VW doubles per vector: 2 is SSE2's
  // width, which every x86-64 has; 4 only inlined into step_avx (a 32-byte vector would pass
  // through memory without AVX).
  template <int N, int VW>
  __attribute__((always_inline)) inline void step_n(const Lanes* x, const Lanes* u, const Lanes* w, double tau,
                                                    int substeps, Lanes* out) {
    // (A vector_size that depends on a template parameter is dropped by GCC: V would be double.)
    using V = std::conditional_t<VW == 2, Double2, Double4>;
    static_assert(sizeof(V) == VW * sizeof(double) && Lanes::kWidth % VW == 0);
    constexpr int kParts = Lanes::kWidth / VW;
#define MARSYN_AT(a, j) load<V>((a).v + VW * (j))
#define MARSYN_PUT(a, j, val) store<V>((a).v + VW * (j), (val))
    const int n = N > 0 ? N : n_;
    Lanes *k1 = scratch_.data(), *k2 = k1 + n, *k3 = k2 + n, *k4 = k3 + n, *y = k4 + n;
    const double h = tau / substeps;
    const V half = V{} + 0.5 * h, full = V{} + h, sixth = V{} + h / 6.0, two = V{} + 2.0;
    auto rhs = [&](const Lanes* state, Lanes* d) {
      f_.field(state, u, d);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < kParts; ++j) MARSYN_PUT(d[i], j, MARSYN_AT(d[i], j) + MARSYN_AT(w[i], j));
    };
    // y = x + c k, the stage point.
    auto point = [&](const V& c, const Lanes* k) {
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < kParts; ++j) MARSYN_PUT(y[i], j, MARSYN_AT(x[i], j) + c * MARSYN_AT(k[i], j));
    };
    rhs(x, k1);
    point(half, k1);
    rhs(y, k2);
    // Stage 3's point against stage 2's, in the columns the field reads.
    bool same = true;
    for (int c : reads_)
      for (int j = 0; j < kParts; ++j) {
        const V next = MARSYN_AT(x[c], j) + half * MARSYN_AT(k2[c], j);
        same = same && std::memcmp(&next, y[c].v + VW * j, sizeof next) == 0;
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
      for (int j = 0; j < kParts; ++j)
        MARSYN_PUT(out[i], j,
                   MARSYN_AT(x[i], j) + sixth * (MARSYN_AT(k1[i], j) + two * MARSYN_AT(k2[i], j) +
                                                 two * MARSYN_AT(k3[i], j) + MARSYN_AT(k4[i], j)));
#undef MARSYN_AT
#undef MARSYN_PUT
  }

  template <class V>
  __attribute__((always_inline)) static V load(const double* p) {
    V v;
    std::memcpy(&v, p, sizeof v);
    return v;
  }
  template <class V>
  __attribute__((always_inline)) static void store(double* p, const V& v) {
    std::memcpy(p, &v, sizeof v);
  }

  const Dynamics& f_;
  int n_;
  std::vector<int> reads_;      // the state columns the field reads
  std::vector<Lanes> scratch_;  // k1..k4 and the stage point: nothing allocated per step
  bool reused_ = false;
#if defined(__x86_64__) && defined(__GNUC__)
  bool avx_ = __builtin_cpu_supports("avx2");
#endif
};

#pragma GCC diagnostic pop

}  // namespace marsyn::verification_detail
