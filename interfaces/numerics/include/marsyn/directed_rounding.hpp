#pragma once
// Directed rounding of +, -, *, / and sqrt without touching the FPU rounding mode: the
// arithmetic under both interval types (marsyn::Interval's rounding policy and FastInterval).
//
// For s = RN(a op b) the exact error a op b - s is itself computable (TwoSum, TwoProduct, the
// division and square-root remainders), and its sign says whether RD/RU is s or its neighbour.
// Inside the ranges checked below the results equal the hardware's directed rounding bit for bit;
// outside them, or when an error term is not finite, the RN result is widened by one ulp, which
// is sound for any correctly rounded operation. Nothing here can be merged or reordered by the
// compiler into a wrong result: every operation runs in the one mode the code was compiled for
// (docs/soundness.md, sections 2 and 7).
//
// Precondition: the calling thread's rounding mode is round-to-nearest (every thread's default).
// Code that cannot rule out a caller's different mode holds a RoundToNearestScope.
#include <algorithm>
#include <bit>
#include <cfenv>
#include <cmath>
#include <cstdint>
#include <limits>

namespace marsyn {

// Sets round-to-nearest for its lifetime if the thread runs in another mode, and restores that
// mode on every exit path (including exceptions). Costs one mode read when nothing needs to
// change.
class RoundToNearestScope {
 public:
  RoundToNearestScope() : saved_(std::fegetround()) {
    if (saved_ != FE_TONEAREST) std::fesetround(FE_TONEAREST);
  }
  ~RoundToNearestScope() {
    if (saved_ != FE_TONEAREST) std::fesetround(saved_);
  }
  RoundToNearestScope(const RoundToNearestScope&) = delete;
  RoundToNearestScope& operator=(const RoundToNearestScope&) = delete;

 private:
  int saved_;
};

namespace fast_detail {

inline bool finite(double x) { return std::fabs(x) <= std::numeric_limits<double>::max(); }

// Neighbours by the bit pattern: for finite x, the next double towards -inf / +inf.
inline double next_down(double x) {
  if (x == 0) return -std::numeric_limits<double>::denorm_min();
  const auto b = std::bit_cast<std::int64_t>(x);
  return std::bit_cast<double>(b > 0 ? b - 1 : b + 1);
}
inline double next_up(double x) {
  if (x == 0) return std::numeric_limits<double>::denorm_min();
  const auto b = std::bit_cast<std::int64_t>(x);
  return std::bit_cast<double>(b > 0 ? b + 1 : b - 1);
}

// Knuth's TwoSum: s + e == a + b exactly in round-to-nearest, unless an intermediate overflows
// (then e is not finite).
inline double two_sum_err(double a, double b, double s) {
  const double bb = s - a;
  const double aa = s - bb;
  return (a - aa) + (b - bb);
}

// TwoProduct: p + e == x * y exactly for p = RN(x y) when no overflow occurs and
// e_x + e_y >= e_min + p - 1 = -970 (Dekker; Handbook of Floating-Point Arithmetic, 4.4). With a
// hardware FMA the error is one fused operation; otherwise Veltkamp splitting (no multiplication
// here may be contracted into an FMA, which the compiler only does when __FMA__ is set).
inline double two_prod_err(double x, double y, double p) {
#ifdef __FMA__
  return __builtin_fma(x, y, -p);
#else
  constexpr double kSplit = 134217729.0;  // 2^27 + 1
  const double cx = kSplit * x, cy = kSplit * y;
  const double xh = cx - (cx - x), xl = x - xh;
  const double yh = cy - (cy - y), yl = y - yh;
  return ((xh * yh - p) + xh * yl + xl * yh) + xl * yl;
#endif
}

// Operands for which TwoProduct is exact and nothing overflows: |x| in [2^-480, 2^480] or x = 0
// (e_x + e_y >= -960, |x y| <= 2^962, 2^27 |x| finite).
inline bool mul_safe(double x) {
  const double a = std::fabs(x);
  return (a >= 0x1p-480 && a <= 0x1p480) || x == 0;
}
// Division a / b: |a| in [2^-240, 2^240] or 0, |b| in [2^-240, 2^240]. Then |q| <= 2^481 and
// e_q + e_b >= -722, so TwoProduct(q, b) is exact and the remainder cannot underflow to zero.
inline bool div_safe(double a, double b) {
  const double x = std::fabs(a), y = std::fabs(b);
  return ((x >= 0x1p-240 && x <= 0x1p240) || a == 0) && y >= 0x1p-240 && y <= 0x1p240;
}

// One ulp outward from a correctly rounded RN result r: always an enclosure of the exact value
// (|exact - r| <= ulp/2, and an overflow to +-inf means |exact| > DBL_MAX).
inline double widen_rn_down(double r) {
  if (finite(r)) return next_down(r);
  return r > 0 ? std::numeric_limits<double>::max() : r;
}
inline double widen_rn_up(double r) {
  if (finite(r)) return next_up(r);
  return r < 0 ? -std::numeric_limits<double>::max() : r;
}

// Directed-rounded scalar operations for finite operands.
inline double add_down(double a, double b) {
  const double s = a + b, e = two_sum_err(a, b, s);
  if (!finite(e)) return widen_rn_down(s);  // an intermediate or the sum overflowed
  return e < 0 ? next_down(s) : s;
}
inline double add_up(double a, double b) {
  const double s = a + b, e = two_sum_err(a, b, s);
  if (!finite(e)) return widen_rn_up(s);
  return e > 0 ? next_up(s) : s;
}
inline double sub_down(double a, double b) { return add_down(a, -b); }
inline double sub_up(double a, double b) { return add_up(a, -b); }

inline double mul_down(double a, double b) {
  const double p = a * b;
  if (!mul_safe(a) || !mul_safe(b)) return widen_rn_down(p);
  return two_prod_err(a, b, p) < 0 ? next_down(p) : p;
}
inline double mul_up(double a, double b) {
  const double p = a * b;
  if (!mul_safe(a) || !mul_safe(b)) return widen_rn_up(p);
  return two_prod_err(a, b, p) > 0 ? next_up(p) : p;
}

// Sign of the exact a / b - q for q = RN(a / b), b != 0: the remainder a - q b equals
// (a - p) - e with (p, e) = TwoProduct(q, b); a - p is exact (Sterbenz: p is within a factor 2 of
// a), and rounding the difference keeps its sign and does not flush a non-zero value to zero.
inline int div_dir(double a, double b, double q) {
  const double p = q * b;
  const double r = (a - p) - two_prod_err(q, b, p);
  if (r == 0) return 0;
  return (r > 0) == (b > 0) ? 1 : -1;
}
inline double div_down(double a, double b) {
  const double q = a / b;
  if (!div_safe(a, b)) return widen_rn_down(q);
  return div_dir(a, b, q) < 0 ? next_down(q) : q;
}
inline double div_up(double a, double b) {
  const double q = a / b;
  if (!div_safe(a, b)) return widen_rn_up(q);
  return div_dir(a, b, q) > 0 ? next_up(q) : q;
}

// x >= 0 finite. Sign of x - s^2 for s = RN(sqrt(x)), exact for x in [2^-960, 2^960] (s in
// [2^-480, 2^480]: TwoProduct(s, s) exact, x - p exact by Sterbenz).
inline int sqrt_dir(double x, double s) {
  const double p = s * s;
  const double r = (x - p) - two_prod_err(s, s, p);
  return r > 0 ? 1 : (r < 0 ? -1 : 0);
}
inline bool sqrt_safe(double x) { return (x >= 0x1p-960 && x <= 0x1p960) || x == 0; }
inline double sqrt_down(double x) {
  const double s = std::sqrt(x);
  if (!sqrt_safe(x)) return std::max(0.0, widen_rn_down(s));
  return sqrt_dir(x, s) < 0 ? next_down(s) : s;
}
inline double sqrt_up(double x) {
  const double s = std::sqrt(x);
  if (!sqrt_safe(x)) return widen_rn_up(s);
  return sqrt_dir(x, s) > 0 ? next_up(s) : s;
}

}  // namespace fast_detail
}  // namespace marsyn
