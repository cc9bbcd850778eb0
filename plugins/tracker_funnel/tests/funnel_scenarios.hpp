#pragma once
// Test agents for the funnel tracker: models of every state dimension the tracker is meant for,
// each with a nominal simulated from smooth inputs (disturbance-free RK4), so that the tests do
// not depend on a planner.
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <string>

#include "dynamics_bicycle/src/bicycle.hpp"
#include "dynamics_cartpole/src/cartpole.hpp"
#include "dynamics_planar_quadrotor/src/planar_quadrotor.hpp"
#include "dynamics_quadrotor/src/quadrotor.hpp"
#include "dynamics_unicycle/src/unicycle.hpp"
#include "marsyn/params.hpp"
#include "marsyn/sampled_map.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn::funnel::testing {

inline Eigen::VectorXd vec(std::initializer_list<double> v) {
  Eigen::VectorXd r(static_cast<int>(v.size()));
  int i = 0;
  for (double x : v) r[i++] = x;
  return r;
}

inline NominalTrajectory simulate(const Dynamics& f, const Eigen::VectorXd& x0, int steps, double tau,
                                  const std::function<Eigen::VectorXd(double t)>& law) {
  NominalTrajectory nom;
  nom.x.push_back(x0);
  for (int k = 0; k < steps; ++k) {
    const Eigen::VectorXd u = law(tau * k);
    Eigen::VectorXd next(x0.size());
    rk4_step<double>(f, nom.x.back().data(), u.data(), nullptr, tau, 8, next.data());
    nom.u.push_back(u);
    nom.x.push_back(next);
  }
  return nom;
}

inline TrackingProblem unicycle(int steps = 60) {
  TrackingProblem p;
  p.agent = "drone";
  p.dynamics = std::make_shared<models::Unicycle>();
  p.tube.eps = vec({0.2, 0.2, 0.24});
  p.tube.w = vec({0.0, 0.025, 0.025});
  p.input_bounds = {vec({-2.4, -2.4}), vec({2.4, 2.4})};
  p.state_bounds = {vec({-1, -1, -2}), vec({11, 11, 3.3})};
  p.nominal = simulate(*p.dynamics, vec({0, 0, M_PI / 4}), steps, p.tau, [](double t) {
    return vec({1.37 + 0.2 * std::sin(0.6 * t), 0.3 * std::sin(2 * M_PI * t / 5.15)});
  });
  return p;
}

// The unicycle with its speed pinned at U's upper bound for 34 of its 60 steps (t in [1.5, 4.8]
// s): the feedback has authority on one side only there (docs/funnel.md, "Inputs at a bound of
// U"), as in the circle swaps, whose nominals run at full speed through the crowd.
inline TrackingProblem unicycle_at_bound(int steps = 60) {
  TrackingProblem p = unicycle(steps);
  p.agent = "pinned";
  p.nominal = simulate(*p.dynamics, vec({0, 0, M_PI / 4}), steps, p.tau, [](double t) {
    return vec({std::min(2.4, 1.6 + 1.2 * std::sin(0.5 * t)), 0.3 * std::sin(2 * M_PI * t / 5.15)});
  });
  return p;
}

// The same with its speed capped at `cap`, just inside U (2.4), and W x 4: the feedback has a
// margin of 2.4 - cap above the nominal, which the LQR gains' input hull over the verified set
// exceeds (docs/funnel.md, "Input-aware weights").
inline TrackingProblem unicycle_near_bound(double cap = 2.35, int steps = 60) {
  TrackingProblem p = unicycle(steps);
  p.agent = "near";
  p.tube.w *= 4.0;
  p.nominal = simulate(*p.dynamics, vec({0, 0, M_PI / 4}), steps, p.tau, [cap](double t) {
    return vec({std::min(cap, 1.6 + 1.2 * std::sin(0.5 * t)), 0.3 * std::sin(2 * M_PI * t / 5.15)});
  });
  return p;
}

inline TrackingProblem crane(int steps = 40) {
  TrackingProblem p;
  p.agent = "crane";
  p.dynamics = std::make_shared<models::CartPole>();
  p.tube.eps = vec({0.135, 0.385, 0.176, 0.768});
  p.tube.w = vec({0, 0.05, 0, 0});
  p.input_bounds = {vec({-7}), vec({7})};
  p.state_bounds = {vec({-0.195, -1.99, 1.20, -5.44}), vec({5.49, 4.37, 4.68, 5.28})};
  p.nominal = simulate(*p.dynamics, vec({0, 0, M_PI, 0}), steps, p.tau, [](double t) {
    return vec({0.62 * std::sin(2 * M_PI * t / 7.0) + 0.5 * std::sin(2 * M_PI * t / 1.4)});
  });
  return p;
}

inline TrackingProblem bicycle(int steps = 50) {
  TrackingProblem p;
  p.agent = "bicycle";
  p.dynamics = std::make_shared<models::Bicycle>();
  p.tube.eps = vec({0.2, 0.2, 0.2, 0.2, 0.15});
  p.tube.w = vec({0.02, 0.02, 0.02, 0.05, 0.02});
  p.input_bounds = {vec({-2, -1.5}), vec({2, 1.5})};
  p.state_bounds = {vec({-10, -10, -4, -1, -0.6}), vec({10, 10, 4, 3, 0.6})};
  p.nominal = simulate(*p.dynamics, vec({0, 0, 0, 1, 0}), steps, p.tau, [](double t) {
    return vec({0.3 * std::sin(0.8 * t), 0.25 * std::cos(1.1 * t)});
  });
  return p;
}

inline TrackingProblem planar_quadrotor(int steps = 50) {
  TrackingProblem p;
  p.agent = "pquad";
  p.dynamics = std::make_shared<models::PlanarQuadrotor>();
  p.tube.eps = vec({0.2, 0.2, 0.2, 0.3, 0.3, 0.5});
  p.tube.w = vec({0, 0, 0, 0.05, 0.05, 0.05});
  p.input_bounds = {vec({5, -8}), vec({15, 8})};
  p.state_bounds = {vec({-10, -10, -1, -5, -5, -5}), vec({10, 10, 1, 5, 5, 5})};
  p.workspace.index = {0, 1};
  p.nominal = simulate(*p.dynamics, vec({0, 1, 0, 0, 0, 0}), steps, p.tau, [](double t) {
    return vec({9.81 + 0.5 * std::sin(t), 0.6 * std::sin(1.3 * t)});
  });
  return p;
}

// The 12-state rigid-body quadrotor near hover: a slow climb with a gentle roll-pitch wobble.
inline TrackingProblem quadrotor(int steps = 30) {
  TrackingProblem p;
  p.agent = "quad";
  p.dynamics = std::make_shared<models::Quadrotor>();
  p.tube.eps = vec({0.2, 0.2, 0.2, 0.15, 0.15, 0.2, 0.3, 0.3, 0.3, 0.6, 0.6, 0.6});
  p.tube.w = vec({0, 0, 0, 0, 0, 0, 0.01, 0.01, 0.01, 0.02, 0.02, 0.02});
  p.input_bounds = {vec({5, -10, -10, -5}), vec({15, 10, 10, 5})};
  p.state_bounds = {vec({-10, -10, -10, -1, -1, -3, -5, -5, -5, -6, -6, -6}), vec({10, 10, 10, 1, 1, 3, 5, 5, 5, 6, 6, 6})};
  p.nominal = simulate(*p.dynamics, vec({0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0}), steps, p.tau, [](double t) {
    return vec({9.81 + 0.3 * std::sin(t), 0.3 * std::sin(1.5 * t), 0.3 * std::cos(1.2 * t), 0.0});
  });
  return p;
}

// The soundness tests run each model over a horizon the funnel verifies today: the enclosures
// outgrow eps after 14 (crane), 20 (bicycle) and 16 (planar quadrotor) steps of these scenarios,
// although the closed loop linearized along the nominal, under the worst disturbance, stays
// within a third to a half of it (docs/tracker.md, "funnel: limits").
// The unicycle under wheel slip that grows with its speed (input v) and, a little, with its
// heading's magnitude: W(x, u) = base + gain_v |v| + gain_theta |theta| (TubeParams::w_growth);
// w is W's largest value over X and U, as the loader computes it.
inline TrackingProblem unicycle_slip(double gain_scale = 1.0) {
  TrackingProblem p = unicycle();
  p.tube.w_base = vec({0.004, 0.004, 0.004});
  p.tube.w_growth = {{true, 0, "v", gain_scale * vec({0.02, 0.02, 0.01})},
                     {false, 2, "theta", gain_scale * vec({0.002, 0.002, 0.0})}};
  p.tube.w = p.tube.w_base + 2.4 * p.tube.w_growth[0].gain + 3.3 * p.tube.w_growth[1].gain;
  return p;
}

inline TrackingProblem scenario(const std::string& name) {
  if (name == "unicycle") return unicycle();
  if (name == "unicycle_slip") return unicycle_slip();
  if (name == "unicycle_at_bound") return unicycle_at_bound();
  if (name == "unicycle_near_bound") return unicycle_near_bound();
  if (name == "crane") return crane(12);
  if (name == "bicycle") return bicycle(18);
  if (name == "planar_quadrotor") return planar_quadrotor(14);
  if (name == "quadrotor") return quadrotor(10);  // 13 steps of this scenario fail
  if (name == "bicycle_split") return bicycle(50);
  throw std::invalid_argument(name);
}

// The tracker parameters of a scenario: bicycle_split starts from a box of half eps, which no
// funnel of the weight ladder verifies without splitting the carried set (step 9 misses y by
// 0.002; with splits at most 3 deep it verifies, docs/funnel.md "Splitting").
inline Params scenario_params(const std::string& name) {
  Params p;
  if (name == "bicycle_split") {
    p.set("initial_fraction", 0.5);
    // Input-aware weights verify it without splits (redesign 1, fill 94.7%): kept out, so that
    // the scenario is split's (docs/funnel.md, "Input-aware weights").
    p.set("input_rounds", 0L);
  }
  return p;
}

}  // namespace marsyn::funnel::testing
