#include "linearization.hpp"

#include <cmath>
#include <limits>

#include "marsyn/scalar.hpp"

namespace marsyn::funnel {

using fast_detail::add_up;
using fast_detail::mul_up;

void interval_jacobian(const Dynamics& f, const FastInterval* X, IMatrix& J, IVector& value) {
  const int n = f.state_dim(), m = f.input_dim(), N = n + m;
  std::vector<DualFI> xd(n), ud(m), out(n);
  for (int i = 0; i < n; ++i) xd[i] = DualFI::variable(X[i], i, N);
  for (int j = 0; j < m; ++j) ud[j] = DualFI::variable(X[n + j], n + j, N);
  f.field(xd.data(), ud.data(), out.data());
  J = IMatrix(n, N);
  value.resize(n);
  for (int i = 0; i < n; ++i) {
    value[i] = out[i].v;
    for (int k = 0; k < N; ++k) J(i, k) = out[i].derivative(k);
  }
}

void interval_hessian(const Dynamics& f, const FastInterval* X, IMatrix& J, std::vector<FastInterval>& H) {
  const int n = f.state_dim(), m = f.input_dim(), N = n + m;
  std::vector<DualFI2> xd(n), ud(m), out(n);
  for (int i = 0; i < n; ++i) xd[i] = second_order_variable_of(X[i], i, N);
  for (int j = 0; j < m; ++j) ud[j] = second_order_variable_of(X[n + j], n + j, N);
  f.field(xd.data(), ud.data(), out.data());
  J = IMatrix(n, N);
  H.assign(static_cast<std::size_t>(n) * N * N, FastInterval(0.0));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < N; ++j) {
      const Dual<FastInterval> dj = out[i].derivative(j);
      J(i, j) = dj.v;
      for (int k = 0; k < N; ++k) H[(static_cast<std::size_t>(i) * N + j) * N + k] = dj.derivative(k);
    }
}

namespace {

// L_i = midpoints of row i of J, bound_i = sum_k |J_ik - L_ik| rad_k rounded up.
void midpoint_rows(const IMatrix& J, const std::vector<double>& rad, Linearization& out) {
  const int n = J.rows, N = J.cols;
  out.L.resize(n, N);
  out.bound.assign(n, 0.0);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < N; ++k) {
      out.L(i, k) = median(J(i, k));
      out.bound[i] = add_up(out.bound[i], mul_up(radius_about(J(i, k), out.L(i, k)), rad[k]));
    }
}

}  // namespace

Linearization mean_value_linearization(const Dynamics& f, const FastInterval* X, const std::vector<double>& rad) {
  IMatrix J;
  IVector unused;
  interval_jacobian(f, X, J, unused);
  Linearization out;
  midpoint_rows(J, rad, out);
  return out;
}

Linearization second_order_linearization(const Dynamics& f, const FastInterval* X, const FastInterval* c,
                                         const std::vector<double>& rad, double scale) {
  const int n = f.state_dim(), N = n + f.input_dim();
  IMatrix JX, Jc;
  IVector unused;
  std::vector<FastInterval> H;
  interval_hessian(f, X, JX, H);
  interval_jacobian(f, c, Jc, unused);
  Linearization out;
  midpoint_rows(Jc, rad, out);
  for (int i = 0; i < n; ++i) {
    double quad = 0.0;
    for (int j = 0; j < N; ++j) {
      if (rad[j] == 0) continue;  // exact: that coordinate does not vary
      double row = 0.0;
      for (int k = 0; k < N; ++k)
        if (rad[k] != 0) row = add_up(row, mul_up(mag(H[(static_cast<std::size_t>(i) * N + j) * N + k]), rad[k]));
      quad = add_up(quad, mul_up(row, rad[j]));
    }
    // Halving is exact; the test hook's factor is rounded up with the product.
    quad = mul_up(quad, 0.5 * scale);
    out.bound[i] = add_up(out.bound[i], quad);
    // A Hessian entry of [-inf, inf] times a zero radius gives NaN: nothing finite is known.
    if (!(out.bound[i] <= std::numeric_limits<double>::max())) out.bound[i] = std::numeric_limits<double>::infinity();
  }
  return out;
}

}  // namespace marsyn::funnel
