#include "membership.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace marsyn::funnel {

namespace {

// The solver over caller-provided, zeroed storage: M (n (p + n)), value and basis (n), at_upper
// and is_basic (p + n). The controller's calls use fixed arrays (no allocation per call).
// Bland's rule (the first improving column) is what the controller and its C export run; the
// most improving column (Dantzig) takes fewer pivots on large zonotopes.
bool solve_phase1(const double* G, int n, int p, const double* d, double* xi, double* M, double* value, int* basis,
                  signed char* at_upper, signed char* is_basic, bool dantzig) {
  // Variables y_j = xi_j + 1 in [0, 2] (j < p) and artificials a_i >= 0 (column p + i), rows
  // G y + s_i a_i = d + G 1 with s_i = sign of the right-hand side, so that y = 0, a = |rhs| is
  // a basic solution. Phase 1 minimises sum a; d is inside when it reaches 0.
  const int cols = p + n;
  auto m = [&](int i, int j) -> double& { return M[static_cast<std::size_t>(i) * cols + j]; };
  double scale = 0.0;
  for (int i = 0; i < n; ++i) {
    double rhs = d[i];
    for (int j = 0; j < p; ++j) {
      rhs += G[i + j * n];
      scale = std::max(scale, std::fabs(G[i + j * n]));
    }
    scale = std::max(scale, std::fabs(d[i]));
    const double s = rhs >= 0 ? 1.0 : -1.0;
    for (int j = 0; j < p; ++j) m(i, j) = s * G[i + j * n];
    m(i, p + i) = 1.0;
    value[i] = std::fabs(rhs);
    basis[i] = p + i;
    is_basic[p + i] = 1;
  }
  if (!(scale > 0) || !std::isfinite(scale)) return !(scale > 0) && scale == 0.0;
  const double tol = 1e-11 * scale, pivot_tol = 1e-9 * scale;
  const int max_iterations = 50 * (n + p) + 100;
  for (int it = 0; it < max_iterations; ++it) {
    // Reduced costs of the y columns (artificials never re-enter): r_j = -sum over basic
    // artificials of M_ij.
    int enter = -1;
    double dir = 0.0, gain = 0.0;
    for (int j = 0; j < p && (enter < 0 || dantzig); ++j) {
      if (is_basic[j]) continue;
      double r = 0.0;
      for (int i = 0; i < n; ++i)
        if (basis[i] >= p) r -= m(i, j);
      if (!at_upper[j] && r < -tol && -r > gain) enter = j, dir = 1.0, gain = -r;
      else if (at_upper[j] && r > tol && r > gain) enter = j, dir = -1.0, gain = r;
    }
    if (enter < 0) break;
    // Ratio test: basics stay in their bounds, the entering variable within [0, 2].
    double theta = 2.0;
    int leave = -1;
    bool leave_to_upper = false;
    for (int i = 0; i < n; ++i) {
      const double a = dir * m(i, enter);
      double limit;
      bool to_upper = false;
      if (a > pivot_tol) {
        limit = value[i] / a;
      } else if (a < -pivot_tol && basis[i] < p) {
        limit = (2.0 - value[i]) / -a;
        to_upper = true;
      } else {
        continue;
      }
      if (limit < theta || (limit == theta && leave >= 0 && basis[i] < basis[leave])) {
        theta = std::max(0.0, limit);
        leave = i;
        leave_to_upper = to_upper;
      }
    }
    for (int i = 0; i < n; ++i) value[i] -= theta * dir * m(i, enter);
    if (leave < 0) {  // the entering variable moves to its other bound
      at_upper[enter] = !at_upper[enter];
      continue;
    }
    const int out = basis[leave];
    is_basic[out] = 0;
    if (out < p) at_upper[out] = leave_to_upper;
    const double entering_value = at_upper[enter] ? 2.0 - theta : theta;
    at_upper[enter] = 0;
    is_basic[enter] = 1;
    basis[leave] = enter;
    value[leave] = entering_value;
    const double piv = m(leave, enter);
    for (int j = 0; j < cols; ++j) m(leave, j) /= piv;
    for (int i = 0; i < n; ++i) {
      if (i == leave) continue;
      const double f = m(i, enter);
      if (f == 0.0) continue;
      for (int j = 0; j < cols; ++j) m(i, j) -= f * m(leave, j);
    }
  }
  double infeasibility = 0.0;
  for (int i = 0; i < n; ++i)
    if (basis[i] >= p) infeasibility += value[i];
  for (int j = 0; j < p; ++j)
    if (!is_basic[j]) xi[j] = at_upper[j] ? 1.0 : -1.0;
  for (int i = 0; i < n; ++i)
    if (basis[i] < p) xi[basis[i]] = std::clamp(value[i] - 1.0, -1.0, 1.0);
  return infeasibility <= 1e-9 * scale;
}

}  // namespace

bool zonotope_coefficients(const double* G, int n, int p, const double* d, double* xi) {
  constexpr int kMaxRows = kMaxMembershipRows;
  for (int j = 0; j < std::clamp(p, 0, kMaxMembershipGenerators); ++j) xi[j] = 0.0;
  if (n < 1 || n > kMaxRows || p < 0 || p > kMaxMembershipGenerators) return false;
  std::array<double, kMaxRows*(kMaxMembershipGenerators + kMaxRows)> M{};
  std::array<double, kMaxRows> value{};
  std::array<int, kMaxRows> basis{};
  std::array<signed char, kMaxMembershipGenerators + kMaxRows> at_upper{};  // nonbasic y at 2
  std::array<signed char, kMaxMembershipGenerators + kMaxRows> is_basic{};
  return solve_phase1(G, n, p, d, xi, M.data(), value.data(), basis.data(), at_upper.data(), is_basic.data(), false);
}

bool zonotope_coefficients_any(const double* G, int n, int p, const double* d, double* xi) {
  if (n < 1 || p < 0) return false;
  for (int j = 0; j < p; ++j) xi[j] = 0.0;
  thread_local std::vector<double> M, value;
  thread_local std::vector<int> basis;
  thread_local std::vector<signed char> at_upper, is_basic;
  M.assign(static_cast<std::size_t>(n) * (p + n), 0.0);
  value.assign(n, 0.0);
  basis.assign(n, 0);
  at_upper.assign(p + n, 0);
  is_basic.assign(p + n, 0);
  return solve_phase1(G, n, p, d, xi, M.data(), value.data(), basis.data(), at_upper.data(), is_basic.data(), true);
}

std::vector<double> least_norm_map(const double* G, int n, int p) {
  if (n < 1 || p < n) return {};
  const Eigen::Map<const Eigen::MatrixXd> g(G, n, p);  // column-major, as stored
  if (!g.allFinite()) return {};
  const Eigen::MatrixXd gram = g * g.transpose();
  Eigen::LLT<Eigen::MatrixXd> llt(gram);
  if (llt.info() != Eigen::Success) return {};
  // A nearly singular G G' gives coefficients the residual test would refuse anyway: skip it.
  const Eigen::VectorXd diag = llt.matrixL().toDenseMatrix().diagonal();
  if (!(diag.minCoeff() > 1e-6 * diag.maxCoeff())) return {};
  const Eigen::MatrixXd P = llt.solve(g).transpose();  // p x n = G' (G G')^-1
  if (!P.allFinite()) return {};
  std::vector<double> out(static_cast<std::size_t>(p) * n);
  for (int j = 0; j < p; ++j)
    for (int i = 0; i < n; ++i) out[static_cast<std::size_t>(j) * n + i] = P(j, i);
  return out;
}

}  // namespace marsyn::funnel
