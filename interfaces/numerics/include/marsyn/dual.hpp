#pragma once
// Forward-mode automatic differentiation over any scalar T (double, or Interval for Jacobian
// enclosures). Deviation from "prefer a library": Eigen's AutoDiffScalar needs Eigen::NumTraits
// for Boost.Interval and allocates when the derivative count is only known at run time; this
// fixed-capacity dual number is heap-free and composes with both scalars.
#include <array>
#include <cmath>
#include <stdexcept>
#include <type_traits>

namespace marsyn {

// Largest number of simultaneous partial derivatives (state + input dimension of one agent).
inline constexpr int kMaxDual = 16;

template <class T>
struct Dual {
  T v{};
  std::array<T, kMaxDual> d{};
  int n = 0;  // number of live derivative slots

  Dual() = default;
  Dual(const T& value) : v(value) {}  // NOLINT: constants promote implicitly
  Dual(double value) requires(!std::is_same_v<T, double>) : v(value) {}  // NOLINT

  // A variable: derivative 1 in slot `slot` of `count` slots.
  static Dual variable(const T& value, int slot, int count) {
    if (count > kMaxDual || slot < 0 || slot >= count)
      throw std::out_of_range("marsyn::Dual: too many derivative directions");
    Dual r(value);
    r.n = count;
    r.d[slot] = T(1.0);
    return r;
  }
  const T& value() const { return v; }
  T derivative(int slot) const { return slot < n ? d[slot] : T(0.0); }
};

namespace dual_detail {
template <class T, class F>
Dual<T> chain(const Dual<T>& a, const T& value, const T& slope, F) {
  Dual<T> r(value);
  r.n = a.n;
  for (int i = 0; i < a.n; ++i) r.d[i] = slope * a.d[i];
  return r;
}
}  // namespace dual_detail

template <class T>
Dual<T> operator+(const Dual<T>& a, const Dual<T>& b) {
  Dual<T> r(a.v + b.v);
  r.n = a.n > b.n ? a.n : b.n;
  for (int i = 0; i < r.n; ++i) r.d[i] = a.derivative(i) + b.derivative(i);
  return r;
}
template <class T>
Dual<T> operator-(const Dual<T>& a, const Dual<T>& b) {
  Dual<T> r(a.v - b.v);
  r.n = a.n > b.n ? a.n : b.n;
  for (int i = 0; i < r.n; ++i) r.d[i] = a.derivative(i) - b.derivative(i);
  return r;
}
template <class T>
Dual<T> operator-(const Dual<T>& a) {
  Dual<T> r(-a.v);
  r.n = a.n;
  for (int i = 0; i < a.n; ++i) r.d[i] = -a.d[i];
  return r;
}
template <class T>
Dual<T> operator*(const Dual<T>& a, const Dual<T>& b) {
  Dual<T> r(a.v * b.v);
  r.n = a.n > b.n ? a.n : b.n;
  for (int i = 0; i < r.n; ++i) r.d[i] = a.derivative(i) * b.v + a.v * b.derivative(i);
  return r;
}
template <class T>
Dual<T> operator/(const Dual<T>& a, const Dual<T>& b) {
  const T q = a.v / b.v;
  Dual<T> r(q);
  r.n = a.n > b.n ? a.n : b.n;
  for (int i = 0; i < r.n; ++i) r.d[i] = (a.derivative(i) - q * b.derivative(i)) / b.v;
  return r;
}
// Mixed operations with plain doubles (model constants).
template <class T> Dual<T> operator+(const Dual<T>& a, double b) { return a + Dual<T>(T(b)); }
template <class T> Dual<T> operator+(double a, const Dual<T>& b) { return Dual<T>(T(a)) + b; }
template <class T> Dual<T> operator-(const Dual<T>& a, double b) { return a - Dual<T>(T(b)); }
template <class T> Dual<T> operator-(double a, const Dual<T>& b) { return Dual<T>(T(a)) - b; }
template <class T> Dual<T> operator*(const Dual<T>& a, double b) {
  Dual<T> r(a.v * b);
  r.n = a.n;
  for (int i = 0; i < a.n; ++i) r.d[i] = a.d[i] * b;
  return r;
}
template <class T> Dual<T> operator*(double a, const Dual<T>& b) { return b * a; }
template <class T> Dual<T> operator/(const Dual<T>& a, double b) { return a / Dual<T>(T(b)); }
template <class T> Dual<T> operator/(double a, const Dual<T>& b) { return Dual<T>(T(a)) / b; }
template <class T> Dual<T>& operator+=(Dual<T>& a, const Dual<T>& b) { return a = a + b; }
template <class T> Dual<T>& operator-=(Dual<T>& a, const Dual<T>& b) { return a = a - b; }
template <class T> Dual<T>& operator*=(Dual<T>& a, const Dual<T>& b) { return a = a * b; }

template <class T>
Dual<T> sin(const Dual<T>& a) {
  using std::cos;
  using std::sin;
  return dual_detail::chain(a, T(sin(a.v)), T(cos(a.v)), 0);
}
template <class T>
Dual<T> cos(const Dual<T>& a) {
  using std::cos;
  using std::sin;
  return dual_detail::chain(a, T(cos(a.v)), T(-sin(a.v)), 0);
}
template <class T>
Dual<T> exp(const Dual<T>& a) {
  using std::exp;
  const T e = exp(a.v);
  return dual_detail::chain(a, e, e, 0);
}
template <class T>
Dual<T> sqrt(const Dual<T>& a) {
  using std::sqrt;
  const T s = sqrt(a.v);
  return dual_detail::chain(a, s, T(0.5) / s, 0);
}
template <class T>
Dual<T> tan(const Dual<T>& a) {
  using std::tan;
  const T t = tan(a.v);
  return dual_detail::chain(a, t, T(1.0) + t * t, 0);
}
template <class T>
Dual<T> atan(const Dual<T>& a) {
  using std::atan;
  return dual_detail::chain(a, T(atan(a.v)), T(1.0) / (T(1.0) + a.v * a.v), 0);
}

// Second-order forward mode (forward over forward): every operation above is written for any
// scalar T, so a Dual whose scalar is itself a Dual<double> carries first derivatives in both
// layers and the exact second derivatives in the derivatives' derivatives. Derivatives are taken
// with respect to the same `count` variables in both layers: y.d[a].d[b] = d^2 y / dz_a dz_b.
using DualD2 = Dual<Dual<double>>;

// Variable `slot` of `count` for second derivatives (seeded in both layers).
inline DualD2 second_order_variable(double value, int slot, int count) {
  return DualD2::variable(Dual<double>::variable(value, slot, count), slot, count);
}
inline double second_derivative(const DualD2& y, int a, int b) { return y.derivative(a).derivative(b); }

// The same seeding over any scalar (e.g. FastInterval: Hessian enclosures over a box).
template <class T>
Dual<Dual<T>> second_order_variable_of(const T& value, int slot, int count) {
  return Dual<Dual<T>>::variable(Dual<T>::variable(value, slot, count), slot, count);
}
template <class T>
T second_derivative_of(const Dual<Dual<T>>& y, int a, int b) {
  return y.derivative(a).derivative(b);
}

}  // namespace marsyn
