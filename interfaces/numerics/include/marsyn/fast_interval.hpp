#pragma once
// Interval arithmetic for hot loops (the tracker's successor boxes, the flow enclosures), sound
// without touching the FPU rounding mode.
//
// A plain pair of doubles over the directed rounding of directed_rounding.hpp: no policy object,
// no mode check per operation, and its own sin/cos/exp/atan with the range reduction the hot
// loops need. Plain double code around these operations (model constants, libm calls) keeps
// running in round-to-nearest, exactly as in a double evaluation of the same model.
// docs/soundness.md section 2 has the argument; interfaces/numerics/tests/fast_interval_test.cpp
// and plugins/tracker_abcd/tests/fast_interval_test.cpp check it.
//
// Precondition: the calling thread's rounding mode is round-to-nearest (every thread's default).
// Code that cannot rule out a caller's different mode holds a RoundToNearestScope.
#include <algorithm>
#include <bit>
#include <cfenv>
#include <cmath>
#include <cstdint>
#include <limits>

#include "marsyn/directed_rounding.hpp"
#include "marsyn/interval.hpp"

namespace marsyn {

namespace fast_detail {

// 2/pi lies strictly between these neighbouring doubles (checked in the tracker's tests against a
// long double reference).
inline constexpr double kTwoOverPiLo = 0x1.45f306dc9c882p-1;
inline constexpr double kTwoOverPiHi = 0x1.45f306dc9c883p-1;

}  // namespace fast_detail

// Closed interval [lo, hi] of doubles. An interval with a NaN bound is empty (as in
// Boost.Interval); any operation with a non-finite operand bound returns the whole line, which
// every consumer treats as "no bound".
class FastInterval {
 public:
  FastInterval() = default;
  FastInterval(double v) : lo_(v), hi_(v) {}  // NOLINT: constants promote implicitly, as in Boost
  FastInterval(double lo, double hi) : lo_(lo), hi_(hi) {
    if (!(lo <= hi)) lo_ = hi_ = std::numeric_limits<double>::quiet_NaN();
  }
  explicit FastInterval(const Interval& x) : lo_(x.lower()), hi_(x.upper()) {}

  double lower() const { return lo_; }
  double upper() const { return hi_; }
  bool finite() const { return fast_detail::finite(lo_) && fast_detail::finite(hi_); }
  Interval to_interval() const { return Interval(lo_, hi_); }

  static FastInterval whole() {
    FastInterval r;
    r.lo_ = -std::numeric_limits<double>::infinity();
    r.hi_ = std::numeric_limits<double>::infinity();
    return r;
  }
  // Bounds already known to be ordered (internal use).
  static FastInterval raw(double lo, double hi) {
    FastInterval r;
    r.lo_ = lo;
    r.hi_ = hi;
    return r;
  }

  FastInterval& operator+=(const FastInterval& o);
  FastInterval& operator-=(const FastInterval& o);
  FastInterval& operator*=(const FastInterval& o);
  FastInterval& operator/=(const FastInterval& o);

 private:
  double lo_ = 0.0, hi_ = 0.0;
};

inline double lower(const FastInterval& x) { return x.lower(); }
inline double upper(const FastInterval& x) { return x.upper(); }
// Rounded up, like boost::numeric::width.
inline double width(const FastInterval& x) {
  if (!x.finite()) return std::numeric_limits<double>::infinity();
  return fast_detail::sub_up(x.upper(), x.lower());
}
// Midpoint in round-to-nearest, like boost::numeric::median.
inline double median(const FastInterval& x) { return (x.lower() + x.upper()) / 2; }
inline bool subset(const FastInterval& a, const FastInterval& b) {
  return b.lower() <= a.lower() && a.upper() <= b.upper();
}
inline FastInterval hull(const FastInterval& a, const FastInterval& b) {
  if (std::isnan(a.lower())) return b;
  if (std::isnan(b.lower())) return a;
  return FastInterval::raw(std::min(a.lower(), b.lower()), std::max(a.upper(), b.upper()));
}
inline bool zero_in(const FastInterval& x) { return x.lower() <= 0 && 0 <= x.upper(); }
// Upper bound of |x|.
inline double mag(const FastInterval& x) { return std::max(-x.lower(), x.upper()); }

inline FastInterval operator+(const FastInterval& a) { return a; }
inline FastInterval operator-(const FastInterval& a) { return FastInterval::raw(-a.upper(), -a.lower()); }

inline FastInterval operator+(const FastInterval& a, const FastInterval& b) {
  if (!a.finite() || !b.finite()) return FastInterval::whole();
  return FastInterval::raw(fast_detail::add_down(a.lower(), b.lower()), fast_detail::add_up(a.upper(), b.upper()));
}
inline FastInterval operator-(const FastInterval& a, const FastInterval& b) {
  if (!a.finite() || !b.finite()) return FastInterval::whole();
  return FastInterval::raw(fast_detail::sub_down(a.lower(), b.upper()), fast_detail::sub_up(a.upper(), b.lower()));
}

// Boost.Interval's sign case analysis: two products unless both factors straddle zero.
inline FastInterval operator*(const FastInterval& x, const FastInterval& y) {
  using fast_detail::mul_down;
  using fast_detail::mul_up;
  if (!x.finite() || !y.finite()) return FastInterval::whole();
  const double xl = x.lower(), xu = x.upper(), yl = y.lower(), yu = y.upper();
  if (xl < 0) {
    if (xu > 0) {
      if (yl < 0) {
        if (yu > 0)  // M * M
          return FastInterval::raw(std::min(mul_down(xl, yu), mul_down(xu, yl)),
                                   std::max(mul_up(xl, yl), mul_up(xu, yu)));
        return FastInterval::raw(mul_down(xu, yl), mul_up(xl, yl));  // M * N
      }
      if (yu > 0) return FastInterval::raw(mul_down(xl, yu), mul_up(xu, yu));  // M * P
      return FastInterval(0.0);                                                // M * Z
    }
    if (yl < 0) {
      if (yu > 0) return FastInterval::raw(mul_down(xl, yu), mul_up(xl, yl));  // N * M
      return FastInterval::raw(mul_down(xu, yu), mul_up(xl, yl));              // N * N
    }
    if (yu > 0) return FastInterval::raw(mul_down(xl, yu), mul_up(xu, yl));  // N * P
    return FastInterval(0.0);                                                // N * Z
  }
  if (xu > 0) {
    if (yl < 0) {
      if (yu > 0) return FastInterval::raw(mul_down(xu, yl), mul_up(xu, yu));  // P * M
      return FastInterval::raw(mul_down(xu, yl), mul_up(xl, yu));              // P * N
    }
    if (yu > 0) return FastInterval::raw(mul_down(xl, yl), mul_up(xu, yu));  // P * P
    return FastInterval(0.0);                                                // P * Z
  }
  return FastInterval(0.0);  // Z * ?
}

// Divisors containing zero are rare (the field would be unbounded there): Boost.Interval's
// semantics, through a conversion.
inline FastInterval operator/(const FastInterval& x, const FastInterval& y) {
  using fast_detail::div_down;
  using fast_detail::div_up;
  if (!x.finite() || !y.finite()) return FastInterval::whole();
  const double xl = x.lower(), xu = x.upper(), yl = y.lower(), yu = y.upper();
  if (yl > 0)
    return FastInterval::raw(xl >= 0 ? div_down(xl, yu) : div_down(xl, yl), xu >= 0 ? div_up(xu, yl) : div_up(xu, yu));
  if (yu < 0)
    return FastInterval::raw(xu >= 0 ? div_down(xu, yu) : div_down(xu, yl), xl >= 0 ? div_up(xl, yl) : div_up(xl, yu));
  const Interval r = x.to_interval() / y.to_interval();
  return FastInterval(r);
}

// Mixed operations with plain doubles (model constants): the double is the point interval.
inline FastInterval operator+(const FastInterval& a, double b) { return a + FastInterval(b); }
inline FastInterval operator+(double a, const FastInterval& b) { return FastInterval(a) + b; }
inline FastInterval operator-(const FastInterval& a, double b) { return a - FastInterval(b); }
inline FastInterval operator-(double a, const FastInterval& b) { return FastInterval(a) - b; }
inline FastInterval operator*(const FastInterval& a, double b) { return a * FastInterval(b); }
inline FastInterval operator*(double a, const FastInterval& b) { return FastInterval(a) * b; }
inline FastInterval operator/(const FastInterval& a, double b) { return a / FastInterval(b); }
inline FastInterval operator/(double a, const FastInterval& b) { return FastInterval(a) / b; }

inline FastInterval& FastInterval::operator+=(const FastInterval& o) { return *this = *this + o; }
inline FastInterval& FastInterval::operator-=(const FastInterval& o) { return *this = *this - o; }
inline FastInterval& FastInterval::operator*=(const FastInterval& o) { return *this = *this * o; }
inline FastInterval& FastInterval::operator/=(const FastInterval& o) { return *this = *this / o; }

inline FastInterval square(const FastInterval& x) {
  if (!x.finite()) return FastInterval::whole();
  const double l = x.lower(), u = x.upper();
  if (l >= 0) return FastInterval::raw(fast_detail::mul_down(l, l), fast_detail::mul_up(u, u));
  if (u <= 0) return FastInterval::raw(fast_detail::mul_down(u, u), fast_detail::mul_up(l, l));
  return FastInterval::raw(0.0, std::max(fast_detail::mul_up(l, l), fast_detail::mul_up(u, u)));
}
inline FastInterval abs(const FastInterval& x) {
  if (x.lower() >= 0) return x;
  if (x.upper() <= 0) return -x;
  return FastInterval::raw(0.0, std::max(-x.lower(), x.upper()));
}

// Boost.Interval's sqrt semantics: the part of x below 0 is outside the domain and ignored; an
// interval entirely below 0 gives the empty interval.
inline FastInterval sqrt(const FastInterval& x) {
  if (std::isnan(x.lower()) || std::isnan(x.upper())) return x;
  if (x.upper() < 0) return FastInterval(1.0, 0.0);
  if (!fast_detail::finite(x.upper())) return FastInterval::raw(x.lower() > 0 ? fast_detail::sqrt_down(x.lower()) : 0.0,
                                                                 std::numeric_limits<double>::infinity());
  return FastInterval::raw(x.lower() > 0 ? fast_detail::sqrt_down(x.lower()) : 0.0, fast_detail::sqrt_up(x.upper()));
}

// libm (called in round-to-nearest, the mode glibc's accuracy figures are given for) widened by
// detail::kTranscUlps ulps, as marsyn::Interval does.
inline FastInterval exp(const FastInterval& x) {
  if (!x.finite()) return FastInterval(boost::numeric::exp(x.to_interval()));
  return FastInterval::raw(std::max(0.0, detail::widen_down(std::exp(x.lower()))), detail::widen_up(std::exp(x.upper())));
}
inline FastInterval atan(const FastInterval& x) {
  if (!x.finite()) return FastInterval(boost::numeric::atan(x.to_interval()));
  return FastInterval::raw(detail::widen_down(std::atan(x.lower())), detail::widen_up(std::atan(x.upper())));
}

namespace fast_detail {
// sin (cos_instead false) or cos over a finite [a, b]. Both are monotone between consecutive
// multiples of pi/2, so the range is the hull of the endpoint values and of the extremes +-1 at
// every multiple m pi/2 inside [a, b]. q encloses [a, b] * 2/pi (directed products with an
// enclosure of 2/pi), so every such m lies in [ceil(q.lo), floor(q.hi)]; taking all of those
// can only add extremes, never miss one. sin is 1 at m = 1 mod 4, -1 at m = 3 mod 4; cos is 1 at
// m = 0 mod 4, -1 at m = 2 mod 4.
inline FastInterval sin_cos(const FastInterval& x, bool cos_instead) {
  const double a = x.lower(), b = x.upper();
  // Beyond 2^40 (or one full period) the quadrant arithmetic is pointless: the range is [-1, 1].
  if (!(std::fabs(a) <= 0x1p40 && std::fabs(b) <= 0x1p40 && b - a < 6.0)) return FastInterval::raw(-1.0, 1.0);
  const double ql = a >= 0 ? mul_down(a, kTwoOverPiLo) : mul_down(a, kTwoOverPiHi);
  const double qh = b >= 0 ? mul_up(b, kTwoOverPiHi) : mul_up(b, kTwoOverPiLo);
  const auto first = static_cast<std::int64_t>(std::ceil(ql)), last = static_cast<std::int64_t>(std::floor(qh));
  const double fa = cos_instead ? std::cos(a) : std::sin(a);
  const double fb = cos_instead ? std::cos(b) : std::sin(b);
  double lo = std::max(-1.0, std::min(detail::widen_down(fa), detail::widen_down(fb)));
  double hi = std::min(1.0, std::max(detail::widen_up(fa), detail::widen_up(fb)));
  const std::int64_t shift = cos_instead ? 0 : 3;  // sin(x) = cos(x - pi/2): m -> m + 3 mod 4
  for (std::int64_t m = first; m <= last && m < first + 4; ++m) {
    const std::int64_t r = ((m + shift) % 4 + 4) % 4;
    if (r == 0) hi = 1.0;
    else if (r == 2) lo = -1.0;
  }
  return FastInterval::raw(lo, hi);
}
}  // namespace fast_detail

inline FastInterval sin(const FastInterval& x) {
  if (!x.finite()) return std::isnan(x.lower()) || std::isnan(x.upper()) ? x : FastInterval::raw(-1.0, 1.0);
  return fast_detail::sin_cos(x, false);
}
inline FastInterval cos(const FastInterval& x) {
  if (!x.finite()) return std::isnan(x.lower()) || std::isnan(x.upper()) ? x : FastInterval::raw(-1.0, 1.0);
  return fast_detail::sin_cos(x, true);
}

// Functions no shipped model uses: Boost.Interval's (with its rounding-mode switches), through a
// conversion, so that models using them still compile and stay sound.
#define MARSYN_FAST_VIA_BOOST(f) \
  inline FastInterval f(const FastInterval& x) { return FastInterval(boost::numeric::f(x.to_interval())); }
MARSYN_FAST_VIA_BOOST(log)
MARSYN_FAST_VIA_BOOST(tan)
MARSYN_FAST_VIA_BOOST(asin)
MARSYN_FAST_VIA_BOOST(acos)
MARSYN_FAST_VIA_BOOST(sinh)
MARSYN_FAST_VIA_BOOST(cosh)
MARSYN_FAST_VIA_BOOST(tanh)
#undef MARSYN_FAST_VIA_BOOST
inline FastInterval pow(const FastInterval& x, int k) { return FastInterval(boost::numeric::pow(x.to_interval(), k)); }

}  // namespace marsyn
