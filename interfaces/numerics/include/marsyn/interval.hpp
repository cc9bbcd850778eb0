#pragma once
// Sound interval arithmetic for enclosures (tracker growth bounds, footprint margins).
//
// Arithmetic and sqrt come from Boost.Interval with directed rounding (IEEE 754 guarantees
// correctly rounded +,-,*,/,sqrt in every rounding mode). Transcendental functions are not
// correctly rounded by libm, so each libm result is widened outward by kTranscUlps units in the
// last place; glibc documents at most 1-2 ulp error for exp/sin/cos/log on x86_64, so 4 ulp is a
// safe margin. Boost.Interval's own range reduction (periodicity, monotone pieces) then yields a
// sound enclosure. See docs/soundness.md.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include <boost/numeric/interval.hpp>

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

using IntervalRounding = boost::numeric::interval_lib::save_state<
    rounded_transc_widened<boost::numeric::interval_lib::rounded_arith_std<double>>>;
using IntervalPolicies =
    boost::numeric::interval_lib::policies<IntervalRounding,
                                           boost::numeric::interval_lib::checking_base<double>>;
}  // namespace detail

// Closed interval [lo, hi] of doubles whose every operation encloses the exact real result.
using Interval = boost::numeric::interval<double, detail::IntervalPolicies>;

inline Interval hull_interval(double a, double b) { return Interval(std::min(a, b), std::max(a, b)); }

}  // namespace marsyn
