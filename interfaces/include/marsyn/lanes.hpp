#pragma once
// Lanes: kWidth doubles computed together, the scalar type of the closed-loop verification's
// integrator. Four runs of one agent advance in lockstep, so a model's vector field (written once
// as a template over the scalar type) is evaluated once for four runs instead of four times.
//
// The arithmetic is lane by lane IEEE double, the scalar's own (the interfaces compile with
// -ffp-contract=off: no contraction into FMA), so a lane computes what `double` computes, except
// the elementary functions when the vector library was found at build time and the CPU has AVX2
// and FMA: sin and cos by the AVX2 kernel below (fdlibm's polynomials, both from one argument
// reduction: sincos()), tan, exp, log, atan, asin, acos, sinh, cosh, tanh by glibc's vector math
// library (libmvec, its AVX2 variants, documented within 4 ulp); lane by lane by libm otherwise. Each lane's result depends on
// that lane's argument only, so a run gives the same states in any batch (alone or with three
// others). Simulation only: no enclosure, certificate or guarantee uses this type.
#include <cmath>

#if defined(MARSYN_HAVE_LIBMVEC) && defined(__x86_64__)
#include <immintrin.h>
#define MARSYN_LANES_VECTOR_MATH 1
#endif

namespace marsyn {

struct Lanes {
  static constexpr int kWidth = 4;
  double v[kWidth];

  Lanes() = default;  // like double: `Lanes x{}` is zero, `Lanes x;` uninitialized (RK4's scratch)
  Lanes(double a) : v{a, a, a, a} {}  // NOLINT: a constant broadcasts, as for every scalar type
  double& operator[](int i) { return v[i]; }
  double operator[](int i) const { return v[i]; }

  Lanes& operator+=(const Lanes& o) { return *this = *this + o; }
  Lanes& operator-=(const Lanes& o) { return *this = *this - o; }
  Lanes& operator*=(const Lanes& o) { return *this = *this * o; }
  Lanes& operator/=(const Lanes& o) { return *this = *this / o; }

  template <class F>
  static Lanes map(const Lanes& a, F f) {
    Lanes r;
    for (int i = 0; i < kWidth; ++i) r.v[i] = f(a.v[i]);
    return r;
  }
  template <class F>
  static Lanes zip(const Lanes& a, const Lanes& b, F f) {
    Lanes r;
    for (int i = 0; i < kWidth; ++i) r.v[i] = f(a.v[i], b.v[i]);
    return r;
  }
  friend Lanes operator+(const Lanes& a) { return a; }
  friend Lanes operator-(const Lanes& a) { return map(a, [](double x) { return -x; }); }
  friend Lanes operator+(const Lanes& a, const Lanes& b) { return zip(a, b, [](double x, double y) { return x + y; }); }
  friend Lanes operator-(const Lanes& a, const Lanes& b) { return zip(a, b, [](double x, double y) { return x - y; }); }
  friend Lanes operator*(const Lanes& a, const Lanes& b) { return zip(a, b, [](double x, double y) { return x * y; }); }
  friend Lanes operator/(const Lanes& a, const Lanes& b) { return zip(a, b, [](double x, double y) { return x / y; }); }
  friend Lanes operator+(const Lanes& a, double b) { return a + Lanes(b); }
  friend Lanes operator+(double a, const Lanes& b) { return Lanes(a) + b; }
  friend Lanes operator-(const Lanes& a, double b) { return a - Lanes(b); }
  friend Lanes operator-(double a, const Lanes& b) { return Lanes(a) - b; }
  friend Lanes operator*(const Lanes& a, double b) { return a * Lanes(b); }
  friend Lanes operator*(double a, const Lanes& b) { return Lanes(a) * b; }
  friend Lanes operator/(const Lanes& a, double b) { return a / Lanes(b); }
  friend Lanes operator/(double a, const Lanes& b) { return Lanes(a) / b; }
};

namespace lanes_detail {

inline void sincos_libm(const Lanes& a, Lanes& s, Lanes& c) {
  s = Lanes::map(a, [](double x) { return std::sin(x); });
  c = Lanes::map(a, [](double x) { return std::cos(x); });
}

#ifdef MARSYN_LANES_VECTOR_MATH
// glibc's libmvec, AVX2 variants (x86-64 vector function ABI names). Declared with the target
// of their callers: clang refuses a 256-bit argument to a function declared without AVX.
#define MARSYN_LANES_AVX2 __attribute__((target("avx2,fma")))
extern "C" {
MARSYN_LANES_AVX2 __m256d _ZGVdN4v_tan(__m256d);
MARSYN_LANES_AVX2 __m256d _ZGVdN4v_exp(__m256d);
MARSYN_LANES_AVX2 __m256d _ZGVdN4v_log(__m256d);
MARSYN_LANES_AVX2 __m256d _ZGVdN4v_atan(__m256d);
MARSYN_LANES_AVX2 __m256d _ZGVdN4v_asin(__m256d);
MARSYN_LANES_AVX2 __m256d _ZGVdN4v_acos(__m256d);
MARSYN_LANES_AVX2 __m256d _ZGVdN4v_sinh(__m256d);
MARSYN_LANES_AVX2 __m256d _ZGVdN4v_cosh(__m256d);
MARSYN_LANES_AVX2 __m256d _ZGVdN4v_tanh(__m256d);
}

// Checked once: the AVX2 variants must not run on a CPU without AVX2.
inline bool vector_math() {
  static const bool ok = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return ok;
}

#define MARSYN_LANES_KERNEL(name)                                                    \
  MARSYN_LANES_AVX2 inline void name##4(const double* x, double* y) { \
    _mm256_storeu_pd(y, _ZGVdN4v_##name(_mm256_loadu_pd(x)));                        \
  }
MARSYN_LANES_KERNEL(tan)
MARSYN_LANES_KERNEL(exp)
MARSYN_LANES_KERNEL(log)
MARSYN_LANES_KERNEL(atan)
MARSYN_LANES_KERNEL(asin)
MARSYN_LANES_KERNEL(acos)
MARSYN_LANES_KERNEL(sinh)
MARSYN_LANES_KERNEL(cosh)
MARSYN_LANES_KERNEL(tanh)
#undef MARSYN_LANES_KERNEL

// sin and cos of four arguments from one reduction (the verification's models take both of one
// angle). |x| <= 1e5: x = n pi/2 + r with pi/2 in four parts, the first three of 33 bits so that
// n times each is exact (|n| < 2^16) and r is exact to far below its last bit even next to a
// multiple of pi/2; then fdlibm's __kernel_sin and __kernel_cos on |r| <= pi/4 (under 1 ulp) and
// the quadrant's swap and signs. Larger or non-finite lanes: libm. Within 4 ulp of libm
// (tests/core/lanes_test.cpp), and each lane depends on its own argument only.
MARSYN_LANES_AVX2 inline void sincos4(const double* xp, double* sp, double* cp) {
  const __m256d x = _mm256_loadu_pd(xp);
  const __m256d n = _mm256_round_pd(_mm256_mul_pd(x, _mm256_set1_pd(6.36619772367581382433e-01)),
                                    _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
  __m256d r = _mm256_sub_pd(x, _mm256_mul_pd(n, _mm256_set1_pd(1.57079632673412561417e+00)));
  r = _mm256_sub_pd(r, _mm256_mul_pd(n, _mm256_set1_pd(6.07710050630396597660e-11)));
  r = _mm256_sub_pd(r, _mm256_mul_pd(n, _mm256_set1_pd(2.02226624871116645580e-21)));
  r = _mm256_sub_pd(r, _mm256_mul_pd(n, _mm256_set1_pd(8.47842766036889956997e-32)));
  const __m256d z = _mm256_mul_pd(r, r);
  __m256d ps = _mm256_set1_pd(1.58969099521155010221e-10);
  ps = _mm256_fmadd_pd(ps, z, _mm256_set1_pd(-2.50507602534068634195e-08));
  ps = _mm256_fmadd_pd(ps, z, _mm256_set1_pd(2.75573137070700676789e-06));
  ps = _mm256_fmadd_pd(ps, z, _mm256_set1_pd(-1.98412698298579493134e-04));
  ps = _mm256_fmadd_pd(ps, z, _mm256_set1_pd(8.33333333332248946124e-03));
  ps = _mm256_fmadd_pd(ps, z, _mm256_set1_pd(-1.66666666666666324348e-01));
  const __m256d sr = _mm256_fmadd_pd(_mm256_mul_pd(z, r), ps, r);  // r + r^3 (S1 + z (S2 + ...))
  __m256d pc = _mm256_set1_pd(-1.13596475577881948265e-11);
  pc = _mm256_fmadd_pd(pc, z, _mm256_set1_pd(2.08757232129817482790e-09));
  pc = _mm256_fmadd_pd(pc, z, _mm256_set1_pd(-2.75573143513906633035e-07));
  pc = _mm256_fmadd_pd(pc, z, _mm256_set1_pd(2.48015872894767294178e-05));
  pc = _mm256_fmadd_pd(pc, z, _mm256_set1_pd(-1.38888888888741095749e-03));
  pc = _mm256_fmadd_pd(pc, z, _mm256_set1_pd(4.16666666666666019037e-02));
  const __m256d one = _mm256_set1_pd(1.0), hz = _mm256_mul_pd(_mm256_set1_pd(0.5), z), w = _mm256_sub_pd(one, hz);
  // 1 - z/2 + z^2 (C1 + ...), summed as fdlibm does so that 1 - z/2 loses nothing.
  const __m256d cr = _mm256_add_pd(w, _mm256_fmadd_pd(_mm256_mul_pd(z, z), pc, _mm256_sub_pd(_mm256_sub_pd(one, w), hz)));
  // Quadrant n mod 4: odd swaps sine and cosine; the sine is negated in 2, 3, the cosine in 1, 2.
  const __m256i q = _mm256_cvtepi32_epi64(_mm256_cvtpd_epi32(n));
  const __m256d odd = _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(q, _mm256_set1_epi64x(1)), _mm256_set1_epi64x(1)));
  const __m256d sneg = _mm256_castsi256_pd(_mm256_slli_epi64(_mm256_srli_epi64(q, 1), 63));
  const __m256d cneg = _mm256_castsi256_pd(_mm256_slli_epi64(_mm256_srli_epi64(_mm256_add_epi64(q, _mm256_set1_epi64x(1)), 1), 63));
  _mm256_storeu_pd(sp, _mm256_xor_pd(_mm256_blendv_pd(sr, cr, odd), sneg));
  _mm256_storeu_pd(cp, _mm256_xor_pd(_mm256_blendv_pd(cr, sr, odd), cneg));
  const __m256d big = _mm256_cmp_pd(_mm256_andnot_pd(_mm256_set1_pd(-0.0), x), _mm256_set1_pd(1e5), _CMP_NLE_UQ);
  if (const int lanes = _mm256_movemask_pd(big))
    for (int l = 0; l < 4; ++l)
      if (lanes >> l & 1) {
        sp[l] = std::sin(xp[l]);
        cp[l] = std::cos(xp[l]);
      }
}
#undef MARSYN_LANES_AVX2
#define MARSYN_LANES_FUNCTION(name)                     \
  inline Lanes name(const Lanes& a) {                   \
    Lanes r;                                            \
    if (lanes_detail::vector_math()) {                  \
      lanes_detail::name##4(a.v, r.v);                  \
      return r;                                         \
    }                                                   \
    return Lanes::map(a, [](double x) { return std::name(x); }); \
  }
inline void sincos(const Lanes& a, Lanes& s, Lanes& c) {
  if (vector_math()) {
    sincos4(a.v, s.v, c.v);
    return;
  }
  sincos_libm(a, s, c);
}
#else
inline constexpr bool vector_math() { return false; }
inline void sincos(const Lanes& a, Lanes& s, Lanes& c) { sincos_libm(a, s, c); }
#define MARSYN_LANES_FUNCTION(name) \
  inline Lanes name(const Lanes& a) { return Lanes::map(a, [](double x) { return std::name(x); }); }
#endif

}  // namespace lanes_detail

// Sine and cosine of four angles at once; sin() and cos() are its two halves, so a model that
// takes both from one call gets the same values as one that calls them apart.
inline void sincos(const Lanes& a, Lanes& s, Lanes& c) { lanes_detail::sincos(a, s, c); }
inline Lanes sin(const Lanes& a) {
  Lanes s, c;
  sincos(a, s, c);
  return s;
}
inline Lanes cos(const Lanes& a) {
  Lanes s, c;
  sincos(a, s, c);
  return c;
}
MARSYN_LANES_FUNCTION(tan)
MARSYN_LANES_FUNCTION(exp)
MARSYN_LANES_FUNCTION(log)
MARSYN_LANES_FUNCTION(atan)
MARSYN_LANES_FUNCTION(asin)
MARSYN_LANES_FUNCTION(acos)
MARSYN_LANES_FUNCTION(sinh)
MARSYN_LANES_FUNCTION(cosh)
MARSYN_LANES_FUNCTION(tanh)
#undef MARSYN_LANES_FUNCTION

// Correctly rounded (IEEE) like the scalar's: lane by lane.
inline Lanes sqrt(const Lanes& a) { return Lanes::map(a, [](double x) { return std::sqrt(x); }); }
inline Lanes abs(const Lanes& a) { return Lanes::map(a, [](double x) { return std::abs(x); }); }
inline Lanes square(const Lanes& a) { return a * a; }
inline Lanes pow(const Lanes& a, int k) { return Lanes::map(a, [k](double x) { return std::pow(x, k); }); }

// True when the elementary functions of Lanes use the vector library (reported by
// `marsyn verify` so that figures from different machines can be compared).
inline bool lanes_vector_math() { return lanes_detail::vector_math(); }

}  // namespace marsyn
