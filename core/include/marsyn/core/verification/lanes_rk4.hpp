#pragma once
// The closed-loop runs' integrator: one RK4 substep of one agent for Lanes::kWidth runs at once,
// lane by lane the arithmetic of rk4_step_lanes(f, x, u, w, tau, substeps, out, 1) bit for bit
// (LanesRk4 in tests/core/lanes_test.cpp), with savings that cannot change a bit:
// - the stage arithmetic on packed vectors (GCC vector extensions: a packed add or multiply rounds
//   each lane as the scalar operation does; the interfaces' -ffp-contract=off keeps them from
//   fusing), where rk4_detail's generic code goes through Lanes' lane loops: the eight lanes in
//   one AVX-512 vector or two AVX2 vectors where the CPU has them (chosen at run time), four SSE2
//   vectors otherwise;
// - a field value taken from an earlier evaluation when every column the field reads
//   (Dynamics::field_independent_of) holds the same bits, in every lane, and so does the input:
//   a field is a function of those columns and the input, so it would give the same bits.
//   Stage 3 from stage 2 (a unicycle's heading rate is its input plus the disturbance, so both
//   stage points have the same heading), and stage 1 from the last substep's stage 4 (the heading
//   advances by h times that rate in both, and x + h (6 r) / 6 rounds to x + h r unless the
//   increment's rounding reaches x's last bit): a unicycle's four sine-cosine evaluations per
//   substep become about two.
// - the four stages as separate calls (start, second, third, finish), so that the closed-loop
//   batch runs one stage of every agent before the next: the agents' fields are independent, and
//   the processor overlaps their sine-cosine latencies (one agent's stages depend on each other).
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
using Double8 = double __attribute__((vector_size(8 * sizeof(double))));

class LanesRk4 {
 public:
  explicit LanesRk4(const Dynamics& f) : f_(f), n_(f.state_dim()), m_(f.input_dim()) {
    const std::vector<bool> free = f.field_independent_of();
    for (int c = 0; c < n_; ++c)
      if (c >= static_cast<int>(free.size()) || !free[static_cast<size_t>(c)]) reads_.push_back(c);
    scratch_.resize(static_cast<size_t>(6 * n_ + m_));
  }

  // out = x after one substep h = tau / substeps under u and w (per lane); out may not alias x.
  void step(const Lanes* x, const Lanes* u, const Lanes* w, double tau, int substeps, Lanes* out) {
    start(x, u, w, tau, substeps);
    second();
    third();
    finish(out);
  }
  // The same substep one stage at a time (in this order; x, u and w are read until finish()).
  void start(const Lanes* x, const Lanes* u, const Lanes* w, double tau, int substeps) {
    x_ = x;
    u_ = u;
    w_ = w;
    h_ = tau / substeps;
    run<1>(nullptr);
  }
  void second() { run<2>(nullptr); }
  void third() { run<3>(nullptr); }
  void finish(Lanes* out) { run<4>(out); }

  // Whether some step so far took stage 3's field from stage 2, stage 1's from the last stage 4
  // (for the tests).
  bool reuses_stage_two() const { return reused_; }
  bool reuses_stage_four() const { return reused_last_; }

 private:
  template <int P>
  void run(Lanes* out) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (avx512_) {
      switch (n_) {
        case 3: return stage_avx512<P, 3>(out);
        case 4: return stage_avx512<P, 4>(out);
        case 6: return stage_avx512<P, 6>(out);
        default: return stage_avx512<P, 0>(out);
      }
    }
    if (avx_) {
      switch (n_) {
        case 3: return stage_avx<P, 3>(out);
        case 4: return stage_avx<P, 4>(out);
        case 6: return stage_avx<P, 6>(out);
        default: return stage_avx<P, 0>(out);
      }
    }
#endif
    // The common state sizes with their loops unrolled (the same operations in the same order).
    switch (n_) {
      case 3: return stage<P, 3, 2>(out);
      case 4: return stage<P, 4, 2>(out);
      case 6: return stage<P, 6, 2>(out);
      default: return stage<P, 0, 2>(out);
    }
  }

#if defined(__x86_64__) && defined(__GNUC__)
  // Four lanes per 256-bit vector where the CPU has AVX2 (the same per-lane IEEE adds and
  // multiplies, unfused: -ffp-contract=off, and no FMA in the target): half the instructions.
  template <int P, int N>
  __attribute__((target("avx2"))) void stage_avx(Lanes* out) {
    stage<P, N, 4>(out);
  }
  // Eight lanes in one 512-bit vector where the CPU has AVX-512 (the same per-lane operations).
  template <int P, int N>
  __attribute__((target("avx512f"))) void stage_avx512(Lanes* out) {
    if constexpr (Lanes::kWidth % 8 == 0) stage<P, N, 8>(out);
    else stage<P, N, 4>(out);
  }
#endif

  // Stage P of the substep. N > 0: n_ == N known at compile time; N == 0: any n_. VW doubles per
  // vector: 2 is SSE2's width, which every x86-64 has; 4 only inlined into stage_avx (a 32-byte
  // vector would pass through memory without AVX).
  template <int P, int N, int VW>
  __attribute__((always_inline)) inline void stage(Lanes* out) {
    // (A vector_size that depends on a template parameter is dropped by GCC: V would be double.)
    using V = std::conditional_t<VW == 2, Double2, std::conditional_t<VW == 4, Double4, Double8>>;
    static_assert(sizeof(V) == VW * sizeof(double) && Lanes::kWidth % VW == 0);
    constexpr int kParts = Lanes::kWidth / VW;
#define MARSYN_AT(a, j) load<V>((a).v + VW * (j))
#define MARSYN_PUT(a, j, val) store<V>((a).v + VW * (j), (val))
    const int n = N > 0 ? N : n_;
    Lanes *k1 = scratch_.data(), *k2 = k1 + n, *k3 = k2 + n, *k4 = k3 + n, *y = k4 + n, *f4 = y + n, *u4 = f4 + n;
    const Lanes *x = x_, *w = w_;
    const double h = h_;
    const V half = V{} + 0.5 * h, full = V{} + h, sixth = V{} + h / 6.0, two = V{} + 2.0;
    // d += w: the disturbance on top of the field.
    auto add_w = [&](Lanes* d) {
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < kParts; ++j) MARSYN_PUT(d[i], j, MARSYN_AT(d[i], j) + MARSYN_AT(w[i], j));
    };
    // y = x + c k, the stage point.
    auto point = [&](const V& c, const Lanes* k) {
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < kParts; ++j) MARSYN_PUT(y[i], j, MARSYN_AT(x[i], j) + c * MARSYN_AT(k[i], j));
    };
    if constexpr (P == 1) {
      // y still holds the last substep's stage-4 point, f4 its field under the input u4.
      bool same = have_f4_;
      for (int i = 0; same && i < m_; ++i) same = std::memcmp(u4[i].v, u_[i].v, sizeof(Lanes)) == 0;
      for (int c : reads_) same = same && std::memcmp(x[c].v, y[c].v, sizeof(Lanes)) == 0;
      if (same) {
        reused_last_ = true;
        for (int i = 0; i < n; ++i) k1[i] = f4[i];
      } else {
        f_.field(x, u_, k1);
      }
      add_w(k1);
      point(half, k1);
    } else if constexpr (P == 2) {
      f_.field(y, u_, k2);
      add_w(k2);
      // Stage 3's point against stage 2's, in the columns the field reads.
      same3_ = true;
      for (int c : reads_)
        for (int j = 0; j < kParts; ++j) {
          const V next = MARSYN_AT(x[c], j) + half * MARSYN_AT(k2[c], j);
          same3_ = same3_ && std::memcmp(&next, y[c].v + VW * j, sizeof next) == 0;
        }
      if (same3_) {
        reused_ = true;
        for (int i = 0; i < n; ++i) k3[i] = k2[i];
      } else {
        point(half, k2);
      }
    } else if constexpr (P == 3) {
      if (!same3_) {
        f_.field(y, u_, k3);
        add_w(k3);
      }
      point(full, k3);
    } else {
      f_.field(y, u_, f4);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < kParts; ++j) MARSYN_PUT(k4[i], j, MARSYN_AT(f4[i], j) + MARSYN_AT(w[i], j));
      for (int i = 0; i < m_; ++i) u4[i] = u_[i];
      have_f4_ = true;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < kParts; ++j)
          MARSYN_PUT(out[i], j,
                     MARSYN_AT(x[i], j) + sixth * (MARSYN_AT(k1[i], j) + two * MARSYN_AT(k2[i], j) +
                                                   two * MARSYN_AT(k3[i], j) + MARSYN_AT(k4[i], j)));
    }
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
  int n_, m_;
  std::vector<int> reads_;      // the state columns the field reads
  std::vector<Lanes> scratch_;  // k1..k4, the stage point, stage 4's field and input: nothing allocated per step
  const Lanes *x_ = nullptr, *u_ = nullptr, *w_ = nullptr;  // the substep's, from start() to finish()
  double h_ = 0;
  bool same3_ = false;   // this substep's stage 3 takes stage 2's field
  bool have_f4_ = false;  // f4 and u4 hold a stage-4 field and its input
  bool reused_ = false, reused_last_ = false;
#if defined(__x86_64__) && defined(__GNUC__)
  bool avx_ = __builtin_cpu_supports("avx2");
  bool avx512_ = Lanes::kWidth % 8 == 0 && __builtin_cpu_supports("avx512f");
#endif
};

#pragma GCC diagnostic pop

}  // namespace marsyn::verification_detail
