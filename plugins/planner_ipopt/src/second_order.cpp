#include "second_order.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "marsyn/sampled_map.hpp"

namespace marsyn::ipopt_planner {

namespace {
// Central differences of exact first derivatives: error O(h^2), h near the cube root of machine
// epsilon.
double fd_step(double v) { return 1e-5 * std::max(1.0, std::abs(v)); }

void symmetrize(int w, double* H) {
  for (int p = 0; p < w; ++p)
    for (int q = 0; q < p; ++q) H[p * w + q] = H[q * w + p] = 0.5 * (H[p * w + q] + H[q * w + p]);
}
}  // namespace

void rk4_weighted_hessian(const SecondOrderField& field, int n, int m, const double* x, const double* u,
                          const double* lam, double tau, int substeps, double* H) {
  const int w = n + m;
  if (w > kMaxDual) throw std::out_of_range("rk4_weighted_hessian: more than kMaxDual variables per agent");
  // marsyn::rk4_step calls Dynamics::field, which has no DualD2 overload; this is its arithmetic
  // over a field callable, line for line, so the Hessian is that of the map the defects use.
  std::vector<DualD2> storage(static_cast<size_t>(6 * n + m));
  DualD2 *k1 = storage.data(), *k2 = k1 + n, *k3 = k2 + n, *k4 = k3 + n, *y = k4 + n, *xs = y + n, *ud = xs + n;
  for (int i = 0; i < n; ++i) xs[i] = second_order_variable(x[i], i, w);
  for (int j = 0; j < m; ++j) ud[j] = second_order_variable(u[j], n + j, w);
  const double h = tau / substeps;
  for (int s = 0; s < substeps; ++s) {
    field(xs, ud, k1);
    for (int i = 0; i < n; ++i) y[i] = xs[i] + (0.5 * h) * k1[i];
    field(y, ud, k2);
    for (int i = 0; i < n; ++i) y[i] = xs[i] + (0.5 * h) * k2[i];
    field(y, ud, k3);
    for (int i = 0; i < n; ++i) y[i] = xs[i] + h * k3[i];
    field(y, ud, k4);
    for (int i = 0; i < n; ++i) xs[i] = xs[i] + (h / 6.0) * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  }
  for (int a = 0; a < w; ++a)
    for (int b = 0; b < w; ++b) {
      double s = 0.0;
      for (int r = 0; r < n; ++r) s += lam[r] * second_derivative(xs[r], a, b);
      H[a * w + b] = s;
    }
}

void differenced_dynamics_hessian(const Dynamics& f, const double* x, const double* u, const double* lam,
                                  double tau, int substeps, int first, double* H) {
  const int n = f.state_dim(), m = f.input_dim(), w = n + m;
  double A[kMaxDual * kMaxDual], B[kMaxDual * kMaxDual];
  std::vector<double> p(w), gp(w), gm(w);
  std::copy(x, x + n, p.begin());
  std::copy(u, u + m, p.begin() + n);
  auto gradient = [&](std::vector<double>& out) {
    rk4_jacobians(f, p.data(), p.data() + n, tau, substeps, nullptr, A, B);
    for (int j = 0; j < w; ++j) {
      double s = 0.0;
      for (int r = 0; r < n; ++r) s += lam[r] * (j < n ? A[r * n + j] : B[r * m + j - n]);
      out[j] = s;
    }
  };
  std::fill(H, H + w * w, 0.0);
  for (int j = first; j < w; ++j) {
    const double z = p[j], step = fd_step(z);
    p[j] = z + step;
    gradient(gp);
    p[j] = z - step;
    gradient(gm);
    p[j] = z;
    for (int r = 0; r < w; ++r) H[r * w + j] = (gp[r] - gm[r]) / (2 * step);
  }
  symmetrize(w, H);
}

void differenced_constraint_hessian(const Constraint& c, const double* x, int n, const double* w, double* H) {
  const auto& s = c.support();
  const int ws = static_cast<int>(s.size()), rows = c.size();
  std::vector<double> xs(x, x + n), g(rows), jp(static_cast<size_t>(rows) * ws), jm(jp.size());
  std::fill(H, H + ws * ws, 0.0);
  for (int j = 0; j < ws; ++j) {
    const double z = xs[s[j]], step = fd_step(z);
    xs[s[j]] = z + step;
    c.evaluate(xs.data(), g.data(), jp.data());
    xs[s[j]] = z - step;
    c.evaluate(xs.data(), g.data(), jm.data());
    xs[s[j]] = z;
    for (int r = 0; r < rows; ++r)
      for (int q = 0; q < ws; ++q) H[q * ws + j] += w[r] * (jp[r * ws + q] - jm[r * ws + q]) / (2 * step);
  }
  symmetrize(ws, H);
}

}  // namespace marsyn::ipopt_planner
