#pragma once
// Lanes: kWidth doubles computed together, the scalar type of the closed-loop verification's
// integrator. Eight runs of one agent advance in lockstep, so a model's vector field (written once
// as a template over the scalar type) is evaluated once for eight runs instead of eight times.
//
// The arithmetic is lane by lane IEEE double, the scalar's own (the interfaces compile with
// -ffp-contract=off: no contraction into FMA), so a lane computes what `double` computes, except
// the elementary functions (sin, cos, tan, exp, log, atan, asin, acos, sinh, cosh, tanh) go to glibc's
// vector math library (libmvec, its AVX2 variants, documented within 4 ulp) when the library was
// found at build time and the CPU has AVX2 and FMA, and lane by lane to libm otherwise (a
// hand-written sin/cos kernel sharing one argument reduction saved 6 % of the 10 drones'
// verification instructions; the library was kept instead). Each lane's result depends on
// that lane's argument only, so a run gives the same states in any batch (alone or with seven
// others). Simulation only: no enclosure, certificate or guarantee uses this type.
#include <cmath>

#if defined(MARSYN_HAVE_LIBMVEC) && defined(__x86_64__)
#include <immintrin.h>
#define MARSYN_LANES_VECTOR_MATH 1
#endif

namespace marsyn {

struct Lanes {
  // Eight runs: two AVX2 vectors (or one AVX-512) per state coordinate, so every call into a
  // model's field and into the vector math library serves twice the runs of four lanes (the
  // library's calls stay four lanes each: the same values as before, lane by lane).
  static constexpr int kWidth = 8;
  double v[kWidth];

  Lanes() = default;  // like double: `Lanes x{}` is zero, `Lanes x;` uninitialized (RK4's scratch)
  Lanes(double a) : v{a, a, a, a, a, a, a, a} {}  // NOLINT: a constant broadcasts, as for every scalar type
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
MARSYN_LANES_AVX2 __m256d _ZGVdN4v_sin(__m256d);
MARSYN_LANES_AVX2 __m256d _ZGVdN4v_cos(__m256d);
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

// All lanes, four at a time (independent calls: the processor overlaps them).
#define MARSYN_LANES_KERNEL(name)                                                    \
  MARSYN_LANES_AVX2 inline void name##4(const double* x, double* y) { \
    for (int i = 0; i < Lanes::kWidth; i += 4)                                       \
      _mm256_storeu_pd(y + i, _ZGVdN4v_##name(_mm256_loadu_pd(x + i)));              \
  }
MARSYN_LANES_KERNEL(sin)
MARSYN_LANES_KERNEL(cos)
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
    sin4(a.v, s.v);
    cos4(a.v, c.v);
    return;
  }
  sincos_libm(a, s, c);
}
MARSYN_LANES_FUNCTION(sin)
MARSYN_LANES_FUNCTION(cos)
#else
inline constexpr bool vector_math() { return false; }
inline void sincos(const Lanes& a, Lanes& s, Lanes& c) { sincos_libm(a, s, c); }
#define MARSYN_LANES_FUNCTION(name) \
  inline Lanes name(const Lanes& a) { return Lanes::map(a, [](double x) { return std::name(x); }); }
MARSYN_LANES_FUNCTION(sin)
MARSYN_LANES_FUNCTION(cos)
#endif

}  // namespace lanes_detail

// Sine and cosine of the lanes at once. sin() and cos() compute one function each (before,
// each called sincos() and dropped half of it: every model with the generic field paid for four
// vector calls where two do) and give sincos()'s halves bit for bit: the same library calls.
// (libmvec's own vector sincos was measured: not faster than its sin and cos apart, and other bits.)
inline void sincos(const Lanes& a, Lanes& s, Lanes& c) { lanes_detail::sincos(a, s, c); }
inline Lanes sin(const Lanes& a) { return lanes_detail::sin(a); }
inline Lanes cos(const Lanes& a) { return lanes_detail::cos(a); }
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
