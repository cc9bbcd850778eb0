#pragma once
// Rounding and measurement allowances of the verification (docs/soundness.md sections 3 and 11),
// shared by the period of the closed loop and the fit of the stored sets.
#include <algorithm>
#include <cmath>

#include "marsyn/fast_interval.hpp"

namespace marsyn::funnel {

// Absolute allowance for products that underflow (gamma bounds relative errors of normal
// numbers only): far above (n + 2) 2^-1074, far below anything a state or input measures.
inline constexpr double kTiny = 1e-300;

// A real state is measured as the nearest double (docs/soundness.md section 3): over [lo, hi]
// the two differ by at most this per coordinate.
inline double measured(double lo, double hi) {
  return fast_detail::mul_up(0x1p-53, std::max(std::fabs(lo), std::fabs(hi)));
}

// Upper bound of max |x_j - ref_j| over the box [lo, hi].
inline double reach(double lo, double hi, double ref) {
  return std::max(std::fabs(fast_detail::sub_up(hi, ref)), std::fabs(fast_detail::sub_up(ref, lo)));
}

}  // namespace marsyn::funnel
