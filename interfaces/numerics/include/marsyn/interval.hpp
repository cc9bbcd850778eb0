#pragma once
// Sound interval arithmetic for enclosures (footprint margins, the equations' and the models'
// interval fields, the certifier's boxes).
//
// Boost.Interval's operations and range reductions (periodicity, monotone pieces) over a rounding
// policy of marsyn's own. Arithmetic and sqrt are rounded outward by the error-free
// transformations of directed_rounding.hpp in round-to-nearest, not by switching the FPU mode as
// Boost's own policy does: under GCC (12, even with -frounding-math) the switching policy is
// unsound on point intervals, because both ends of Interval(a) - Interval(b) are the one
// expression a - b, which the compiler computes once, in whichever mode comes first
// (docs/soundness.md, section 7). Transcendental functions are not correctly rounded by libm, so
// each libm result is widened outward by kTranscUlps units in the last place; glibc documents at
// most 1-2 ulp error for exp/sin/cos/log on x86_64 in round-to-nearest, so 4 ulp is a safe
// margin.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include <boost/numeric/interval.hpp>

#include "marsyn/directed_rounding.hpp"

namespace marsyn {
namespace detail {

inline constexpr int kTranscUlps = 4;

// kTranscUlps steps of nextafter. Away from zero and from overflow the steps stay within one
// sign, where consecutive doubles have consecutive bit patterns: one integer addition gives the
// same double as the steps (a libm call each: half of an interval sine's cost). Elsewhere (zero,
// subnormals near it, the largest doubles, inf, NaN) the steps themselves.
inline bool widen_by_bits(double v) {
  const std::uint64_t mag = std::bit_cast<std::uint64_t>(v) & 0x7fffffffffffffffULL;
  return mag >= static_cast<std::uint64_t>(kTranscUlps) &&
         mag <= std::bit_cast<std::uint64_t>(std::numeric_limits<double>::max()) - kTranscUlps;
}
inline double widen_down(double v) {
  if (widen_by_bits(v)) {
    const std::uint64_t b = std::bit_cast<std::uint64_t>(v);
    return std::bit_cast<double>(v > 0 ? b - kTranscUlps : b + kTranscUlps);
  }
  for (int i = 0; i < kTranscUlps; ++i) v = std::nextafter(v, -std::numeric_limits<double>::infinity());
  return v;
}
inline double widen_up(double v) {
  if (widen_by_bits(v)) {
    const std::uint64_t b = std::bit_cast<std::uint64_t>(v);
    return std::bit_cast<double>(v > 0 ? b + kTranscUlps : b - kTranscUlps);
  }
  for (int i = 0; i < kTranscUlps; ++i) v = std::nextafter(v, std::numeric_limits<double>::infinity());
  return v;
}

// Boost.Interval rounding policy: exact rounding for arithmetic, ulp-widened libm for the rest.
template <class Rounding>
struct rounded_transc_widened : Rounding {
#define MARSYN_WIDENED(f)                                            \
  double f##_down(const double& x) { return widen_down(std::f(x)); } \
  double f##_up(const double& x) { return widen_up(std::f(x)); }
  MARSYN_WIDENED(exp)
  MARSYN_WIDENED(log)
  MARSYN_WIDENED(tan)
  MARSYN_WIDENED(asin)
  MARSYN_WIDENED(acos)
  MARSYN_WIDENED(atan)
  MARSYN_WIDENED(sinh)
  MARSYN_WIDENED(cosh)
  MARSYN_WIDENED(tanh)
  MARSYN_WIDENED(asinh)
  MARSYN_WIDENED(acosh)
  MARSYN_WIDENED(atanh)
#undef MARSYN_WIDENED
  // sin and cos never leave [-1, 1]; clamping keeps the widening from breaking that.
  double sin_down(const double& x) { return std::max(-1.0, widen_down(std::sin(x))); }
  double sin_up(const double& x) { return std::min(1.0, widen_up(std::sin(x))); }
  double cos_down(const double& x) { return std::max(-1.0, widen_down(std::cos(x))); }
  double cos_up(const double& x) { return std::min(1.0, widen_up(std::cos(x))); }
};

// Boost.Interval rounding policy: directed +, -, *, /, sqrt by error-free transformations in
// round-to-nearest. The mode-switching members Boost's own code may call are no-ops: nothing
// here depends on the FPU mode.
struct rounded_arith_error_free {
  using rounding_mode = int;
  static void get_rounding_mode(rounding_mode&) {}
  static void set_rounding_mode(rounding_mode) {}
  static void upward() {}
  static void downward() {}
  static void to_nearest() {}
  static double to_int(double x) { return std::nearbyint(x); }
  static double force_rounding(double x) { return x; }
  void init() {}
  // Conversions: doubles and floats are exact; wider integers and long doubles are rounded to
  // nearest and stepped outward when that went the wrong way (long double holds every 64-bit
  // integer exactly).
  template <class U>
  double conv_down(const U& v) {
    const double d = static_cast<double>(v);
    if constexpr (std::is_same_v<U, double> || std::is_same_v<U, float>) return d;
    else return static_cast<long double>(d) > static_cast<long double>(v) ? fast_detail::next_down(d) : d;
  }
  template <class U>
  double conv_up(const U& v) {
    const double d = static_cast<double>(v);
    if constexpr (std::is_same_v<U, double> || std::is_same_v<U, float>) return d;
    else return static_cast<long double>(d) < static_cast<long double>(v) ? fast_detail::next_up(d) : d;
  }
  static double add_down(double x, double y) { return fast_detail::add_down(x, y); }
  static double add_up(double x, double y) { return fast_detail::add_up(x, y); }
  static double sub_down(double x, double y) { return fast_detail::sub_down(x, y); }
  static double sub_up(double x, double y) { return fast_detail::sub_up(x, y); }
  static double mul_down(double x, double y) { return fast_detail::mul_down(x, y); }
  static double mul_up(double x, double y) { return fast_detail::mul_up(x, y); }
  static double div_down(double x, double y) { return fast_detail::div_down(x, y); }
  static double div_up(double x, double y) { return fast_detail::div_up(x, y); }
  static double median(double x, double y) { return (x + y) / 2; }
  static double sqrt_down(double x) { return fast_detail::sqrt_down(x); }
  static double sqrt_up(double x) { return fast_detail::sqrt_up(x); }
  static double int_down(double x) { return std::floor(x); }
  static double int_up(double x) { return std::ceil(x); }
};

// Round-to-nearest for the duration of one protected operation (the error-free transformations
// and the libm bounds assume it): a mode read when the caller is already there, as every thread
// is by default; a switch and a restore otherwise.
template <class Rounding>
struct nearest_state : Rounding {
  RoundToNearestScope nearest;
  using unprotected_rounding = boost::numeric::interval_lib::save_state_nothing<Rounding>;
};

using IntervalRounding = nearest_state<rounded_transc_widened<rounded_arith_error_free>>;
using IntervalPolicies =
    boost::numeric::interval_lib::policies<IntervalRounding,
                                           boost::numeric::interval_lib::checking_base<double>>;
}  // namespace detail

// Closed interval [lo, hi] of doubles whose every operation encloses the exact real result.
using Interval = boost::numeric::interval<double, detail::IntervalPolicies>;

inline Interval hull_interval(double a, double b) { return Interval(std::min(a, b), std::max(a, b)); }

}  // namespace marsyn
