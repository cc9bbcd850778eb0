#pragma once
// The abcd tests' closed loop of one agent under its controller, independent of the abstraction:
// many classical RK4 substeps per sampling period on the true field plus a disturbance, and the
// tube checked at the samples. Test-only: marsyn's closed-loop simulator is core's
// (core/src/verification/closed_loop.cpp, all agents, the spec dense in time); a plugin cannot
// link core, and this one's disturbance modes (TubeDisturbance: UniformRandom redraws at every
// substep) are not core's DisturbanceMode.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "marsyn/dynamics.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn {

enum class TubeDisturbance {
  None,            // w = 0
  ConstantVertex,  // w fixed at one vertex of [-W, W] for the whole run (vertex given)
  UniformRandom,   // w uniform in [-W, W], redrawn at every integration substep
  VertexSwitching  // a random vertex of [-W, W], redrawn at every sampling step
};

inline const char* to_string(TubeDisturbance m) {
  switch (m) {
    case TubeDisturbance::None: return "none";
    case TubeDisturbance::ConstantVertex: return "constant vertex";
    case TubeDisturbance::UniformRandom: return "uniform random";
    case TubeDisturbance::VertexSwitching: return "vertex switching";
  }
  return "?";
}

struct ClosedLoopOptions {
  TubeDisturbance mode = TubeDisturbance::None;
  std::uint64_t vertex = 0;  // ConstantVertex: bit i set means +W_i, clear means -W_i
  std::uint64_t seed = 1;
  int substeps = 50;
  double tau = 0.1;
};

struct ClosedLoopResult {
  std::vector<Eigen::VectorXd> x, u;  // visited states x_0..x_K and applied inputs
  int steps = 0;                      // steps simulated
  int first_violation = -1;           // first k with |x_k - nominal_k| > eps, -1 if none
  int controller_gave_up = -1;        // first k < T where input() was not Ok, -1 if none
  bool in_tube() const { return first_violation < 0 && controller_gave_up < 0; }
};

// Integrates x' = f(x, u) + w(t) over one sampling period with `substeps` RK4 steps; w is
// piecewise constant on substeps (taken from wfun(substep)).
template <class WFun>
Eigen::VectorXd integrate_period(const Dynamics& f, const Eigen::VectorXd& x0, const double* u, double tau, int substeps,
                                 WFun wfun) {
  const int n = f.state_dim();
  Eigen::VectorXd x = x0, y(n), k1(n), k2(n), k3(n), k4(n);
  const double h = tau / substeps;
  for (int s = 0; s < substeps; ++s) {
    const Eigen::VectorXd w = wfun(s);
    auto rhs = [&](const Eigen::VectorXd& z, Eigen::VectorXd& d) {
      f.field(z.data(), u, d.data());
      d += w;
    };
    rhs(x, k1);
    y = x + 0.5 * h * k1;
    rhs(y, k2);
    y = x + 0.5 * h * k2;
    rhs(y, k3);
    y = x + h * k3;
    rhs(y, k4);
    x += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return x;
}

// Runs the controller from x0 along `nominal` (states x_0..x_T) and checks the tube.
inline ClosedLoopResult simulate_closed_loop(const Dynamics& f, const Controller& c, const Eigen::VectorXd& x0,
                                             const std::vector<Eigen::VectorXd>& nominal, const Eigen::VectorXd& eps,
                                             const Eigen::VectorXd& W, const ClosedLoopOptions& o) {
  const int n = f.state_dim(), m = f.input_dim();
  const int T = static_cast<int>(nominal.size()) - 1;
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  auto vertex = [&](std::uint64_t bits) {
    Eigen::VectorXd w(n);
    for (int i = 0; i < n; ++i) w[i] = ((bits >> i) & 1u) ? W[i] : -W[i];
    return w;
  };
  ClosedLoopResult r;
  Eigen::VectorXd x = x0;
  r.x.push_back(x);
  auto outside = [&](int k) { return ((x - nominal[static_cast<size_t>(k)]).cwiseAbs().array() > eps.array()).any(); };
  if (outside(0)) r.first_violation = 0;
  for (int k = 0; k < T && r.in_tube(); ++k) {
    Eigen::VectorXd u(m);
    if (c.input(x.data(), k, u.data()) != ControlStatus::Ok) {
      r.controller_gave_up = k;
      break;
    }
    r.u.push_back(u);
    const Eigen::VectorXd step_vertex = vertex(rng());
    auto wfun = [&](int) -> Eigen::VectorXd {
      switch (o.mode) {
        case TubeDisturbance::None: return Eigen::VectorXd::Zero(n);
        case TubeDisturbance::ConstantVertex: return vertex(o.vertex);
        case TubeDisturbance::VertexSwitching: return step_vertex;
        case TubeDisturbance::UniformRandom: {
          Eigen::VectorXd w(n);
          for (int i = 0; i < n; ++i) w[i] = W[i] * unit(rng);
          return w;
        }
      }
      return Eigen::VectorXd::Zero(n);
    };
    x = integrate_period(f, x, u.data(), o.tau, o.substeps, wfun);
    r.x.push_back(x);
    r.steps = k + 1;
    if (outside(k + 1)) r.first_violation = k + 1;
  }
  return r;
}

}  // namespace marsyn
