#pragma once
// The operations of an equation program for every scalar type of the Dynamics interface
// (double, DualD, DualD2, Interval, DualI, FastInterval, DualFI). Where marsyn's headers already
// define a function for a type, that very overload is called (unqualified, after `using std::f`),
// so an equation model computes what a C++ plugin writing the same expression computes. The
// additions here are log and integer powers for the dual numbers (chain rule over the scalar
// below, so they nest for DualD2) and the tight interval square.
#include <cmath>

#include "marsyn/lanes.hpp"
#include "marsyn/scalar.hpp"

namespace marsyn::equations::ops {

template <class S> S fn_sin(const S& x) { using std::sin; return sin(x); }
template <class S> S fn_cos(const S& x) { using std::cos; return cos(x); }
template <class S> S fn_tan(const S& x) { using std::tan; return tan(x); }
template <class S> S fn_exp(const S& x) { using std::exp; return exp(x); }
template <class S> S fn_sqrt(const S& x) { using std::sqrt; return sqrt(x); }
template <class S> S fn_atan(const S& x) { using std::atan; return atan(x); }

// log: libm for double; Boost.Interval's (ulp-widened libm, interval.hpp) for Interval;
// FastInterval's (the same through a conversion) for FastInterval; d log a = da / a for duals.
inline double fn_log(double x) { return std::log(x); }
inline Interval fn_log(const Interval& x) { return boost::numeric::log(x); }
inline FastInterval fn_log(const FastInterval& x) { return marsyn::log(x); }
inline Lanes fn_log(const Lanes& x) { return marsyn::log(x); }
template <class T>
Dual<T> fn_log(const Dual<T>& a) {
  return dual_detail::chain(a, fn_log(a.v), T(1.0) / a.v, 0);
}

// x^k for an integer k >= 2 (the parser turns k <= 1 into other nodes). Intervals: the tight
// even/odd power (Boost.Interval's pow, square for k = 2), not k-fold products.
inline double fn_pow(double x, int k) { return std::pow(x, k); }
inline Interval fn_pow(const Interval& x, int k) { return k == 2 ? boost::numeric::square(x) : boost::numeric::pow(x, k); }
inline FastInterval fn_pow(const FastInterval& x, int k) { return k == 2 ? marsyn::square(x) : marsyn::pow(x, k); }
inline Lanes fn_pow(const Lanes& x, int k) { return marsyn::pow(x, k); }
template <class T>
Dual<T> fn_pow(const Dual<T>& a, int k) {
  const T slope = k == 2 ? T(2.0) * a.v : T(static_cast<double>(k)) * fn_pow(a.v, k - 1);
  return dual_detail::chain(a, fn_pow(a.v, k), slope, 0);
}

}  // namespace marsyn::equations::ops
