#pragma once
// The sampled map f_tau: classical RK4 with `substeps` equal steps over one sampling period tau,
// with a constant disturbance w added to the right-hand side. Templated so that the same code
// gives states (double) and exact discrete Jacobians (DualD). It is an approximation of the
// flow; trackers never rely on it for soundness (they enclose the flow, docs/soundness.md).
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "marsyn/dynamics.hpp"

namespace marsyn {

namespace rk4_detail {

// `steps` of the `substeps` equal RK4 steps over tau (all when steps < 0), w (one per state, or
// null) added to the right-hand side. W is double, or Lanes with S (one disturbance per lane).
template <class S, class W>
void run(const Dynamics& f, const S* x, const S* u, const W* w, double tau, int substeps, S* out, int steps) {
  const int n = f.state_dim();
  // Planner rollouts call this T x N times per line-search trial: agent-sized systems use stack
  // storage, only larger ones (a product of agents) the heap.
  std::array<S, 6 * kMaxDual> stack_storage;
  std::vector<S> heap_storage;
  S* storage = stack_storage.data();
  if (n > kMaxDual) {
    heap_storage.resize(static_cast<std::size_t>(6 * n));
    storage = heap_storage.data();
  }
  S *k1 = storage, *k2 = k1 + n, *k3 = k2 + n, *k4 = k3 + n, *y = k4 + n, *xs = y + n;
  for (int i = 0; i < n; ++i) xs[i] = x[i];
  const double h = tau / substeps;
  auto rhs = [&](const S* state, S* d) {
    f.field(state, u, d);
    if (w)
      for (int i = 0; i < n; ++i) d[i] = d[i] + w[i];
  };
  const int count = steps < 0 ? substeps : steps;
  for (int s = 0; s < count; ++s) {
    rhs(xs, k1);
    for (int i = 0; i < n; ++i) y[i] = xs[i] + (0.5 * h) * k1[i];
    rhs(y, k2);
    for (int i = 0; i < n; ++i) y[i] = xs[i] + (0.5 * h) * k2[i];
    rhs(y, k3);
    for (int i = 0; i < n; ++i) y[i] = xs[i] + h * k3[i];
    rhs(y, k4);
    for (int i = 0; i < n; ++i) xs[i] = xs[i] + (h / 6.0) * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  }
  for (int i = 0; i < n; ++i) out[i] = xs[i];
}

}  // namespace rk4_detail

// steps >= 0: only the first `steps` of the substeps (dense output between the samples, with
// the same arithmetic as the whole step).
template <class S>
void rk4_step(const Dynamics& f, const S* x, const S* u, const double* w, double tau, int substeps,
              S* out, int steps = -1) {
  rk4_detail::run<S, double>(f, x, u, w, tau, substeps, out, steps);
}

// rk4_step for four states at once (lanes.hpp), each lane with its own disturbance: lane by lane
// the arithmetic of rk4_step<double>.
inline void rk4_step_lanes(const Dynamics& f, const Lanes* x, const Lanes* u, const Lanes* w, double tau,
                           int substeps, Lanes* out, int steps = -1) {
  rk4_detail::run<Lanes, Lanes>(f, x, u, w, tau, substeps, out, steps);
}

// Discrete Jacobians A = d f_tau / dx, B = d f_tau / du (row-major n x n and n x m), exact for
// the RK4 map by forward-mode AD.
inline void rk4_jacobians(const Dynamics& f, const double* x, const double* u, double tau, int substeps,
                          double* next, double* A, double* B) {
  const int n = f.state_dim(), m = f.input_dim();
  std::vector<DualD> xd(n), ud(m), out(n);
  for (int i = 0; i < n; ++i) xd[i] = DualD::variable(x[i], i, n + m);
  for (int j = 0; j < m; ++j) ud[j] = DualD::variable(u[j], n + j, n + m);
  rk4_step<DualD>(f, xd.data(), ud.data(), nullptr, tau, substeps, out.data());
  for (int i = 0; i < n; ++i) {
    if (next) next[i] = out[i].v;
    for (int j = 0; j < n; ++j) A[i * n + j] = out[i].derivative(j);
    for (int j = 0; j < m; ++j) B[i * m + j] = out[i].derivative(n + j);
  }
}

// The interior point j (1..points) of a period: RK4 from x under u over the fraction
// j / (points + 1) of tau with about the sampled map's step length (its substeps scaled, at least
// one): with points + 1 == substeps, the map's own substep states up to rounding.
struct FlowPointStep {
  double h = 0.0;  // length of the partial period, s
  int substeps = 1;
};
inline FlowPointStep flow_point_step(double tau, int substeps, int j, int points) {
  const double f = static_cast<double>(j) / (points + 1);
  FlowPointStep s;
  s.h = tau * f;
  s.substeps = std::max(1, static_cast<int>(std::ceil(substeps * f - 1e-9)));
  return s;
}

// The interior point j of a period (PlanningProblem::between_points): the
// RK4 state after the fraction j / (points + 1) of tau from x under u, and when A, B are
// non-null its exact Jacobians in x and u (row-major n x n, n x m).
inline void flow_point(const Dynamics& f, const double* x, const double* u, double tau, int substeps, int j,
                       int points, double* out, double* A, double* B) {
  const FlowPointStep s = flow_point_step(tau, substeps, j, points);
  if (A && B) rk4_jacobians(f, x, u, s.h, s.substeps, out, A, B);
  else rk4_step<double>(f, x, u, nullptr, s.h, s.substeps, out);
}

// Every interior point of a period at once: out[(j - 1) * n ...] for j = 1..points. When
// points + 1 == substeps they are the sampled map's own substep states, one substep apart (the
// same arithmetic as rk4_step), so they cost less than one step of the map.
inline void flow_points(const Dynamics& f, const double* x, const double* u, double tau, int substeps, int points,
                        double* out) {
  const int n = f.state_dim();
  if (points + 1 == substeps) {
    const double* from = x;
    for (int j = 1; j <= points; ++j) {
      rk4_step<double>(f, from, u, nullptr, tau, substeps, out + (j - 1) * n, 1);
      from = out + (j - 1) * n;
    }
    return;
  }
  for (int j = 1; j <= points; ++j) flow_point(f, x, u, tau, substeps, j, points, out + (j - 1) * n, nullptr, nullptr);
}

}  // namespace marsyn
