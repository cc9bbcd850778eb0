#pragma once
// Example agents with the case studies' parameters and nominal trajectories simulated from fixed
// smooth inputs (disturbance-free, fine RK4), for tests and the benchmark.
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "tube_simulation.hpp"
#include "dynamics_cartpole/src/cartpole.hpp"
#include "dynamics_double_integrator/src/double_integrator.hpp"
#include "dynamics_pendulum/src/pendulum.hpp"
#include "dynamics_unicycle/src/unicycle.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn::abcd::scenarios {

inline Eigen::VectorXd vec(std::initializer_list<double> v) {
  Eigen::VectorXd r(static_cast<int>(v.size()));
  int i = 0;
  for (double x : v) r[i++] = x;
  return r;
}

// Input at step k (and the state, for feedback-generated nominals).
using InputLaw = std::function<Eigen::VectorXd(int k, const Eigen::VectorXd& x)>;

inline NominalTrajectory simulate_nominal(const Dynamics& f, const Eigen::VectorXd& x0, int steps, double tau,
                                          const InputLaw& law) {
  NominalTrajectory nom;
  nom.x.push_back(x0);
  for (int k = 0; k < steps; ++k) {
    const Eigen::VectorXd u = law(k, nom.x.back());
    nom.u.push_back(u);
    nom.x.push_back(integrate_period(f, nom.x.back(), u.data(), tau, 50,
                                     [&](int) { return Eigen::VectorXd::Zero(f.state_dim()).eval(); }));
  }
  return nom;
}

inline TrackingProblem drone(int steps = 103) {
  TrackingProblem p;
  p.agent = "drone";
  p.dynamics = std::make_shared<models::Unicycle>();
  p.tube.eps = vec({0.2, 0.2, 0.24});
  p.fields.set("eta_x", vec({0.025, 0.025, 0.03}));
  p.fields.set("eta_u", vec({0.3, 0.3}));
  p.tube.w = vec({0.0, 0.025, 0.025});
  p.input_bounds = {vec({-2.4, -2.4}), vec({2.4, 2.4})};
  p.state_bounds = {vec({-1, -1, -2}), vec({11, 11, 3.3})};
  p.nominal = simulate_nominal(*p.dynamics, vec({0, 0, M_PI / 4}), steps, p.tau, [](int k, const Eigen::VectorXd&) {
    const double t = 0.1 * k;
    return vec({1.37 + 0.2 * std::sin(0.6 * t), 0.3 * std::sin(2 * M_PI * t / 5.15)});
  });
  return p;
}

inline TrackingProblem lane_merging() {
  TrackingProblem p;
  p.agent = "lane_car";
  p.dynamics = std::make_shared<models::Unicycle>();
  p.tube.eps = vec({0.16, 0.16, 0.16});
  p.fields.set("eta_x", vec({0.02, 0.02, 0.02}));
  p.fields.set("eta_u", vec({0.3, 0.15}));
  p.tube.w = vec({0.03, 0.03, 0.03});
  p.input_bounds = {vec({-0.9, -2.1}), vec({3, 2.1})};
  p.state_bounds = {vec({-0.5, 0.1, -1}), vec({15, 7.4, 0.4})};
  p.nominal = simulate_nominal(*p.dynamics, vec({8, 3.9, -0.64}), 110, p.tau, [](int k, const Eigen::VectorXd&) {
    const double t = 0.1 * k;
    return vec({1.2 + 0.3 * std::sin(0.3 * t), 0.4 * std::exp(-0.5 * t) * std::cos(0.5 * t)});
  });
  return p;
}

inline TrackingProblem formation() {
  TrackingProblem p;
  p.agent = "formation_drone";
  p.dynamics = std::make_shared<models::Unicycle>();
  p.tube.eps = vec({0.24, 0.24, 0.24});
  p.fields.set("eta_x", vec({0.03, 0.03, 0.03}));
  p.fields.set("eta_u", vec({0.3, 0.15}));
  p.tube.w = vec({0.03, 0.03, 0.03});
  p.input_bounds = {vec({-0.9, -3}), vec({4.8, 3})};
  p.state_bounds = {vec({-2, -2, 0.6}), vec({17, 17, 1.6})};
  p.nominal = simulate_nominal(*p.dynamics, vec({0, 0, M_PI / 4}), 100, p.tau, [](int k, const Eigen::VectorXd&) {
    const double t = 0.1 * k;
    return vec({2.1, 0.25 * std::sin(0.7 * t)});
  });
  return p;
}

inline TrackingProblem crane(int steps = 70) {
  TrackingProblem p;
  p.agent = "crane";
  p.dynamics = std::make_shared<models::CartPole>();
  p.tube.eps = vec({0.135, 0.385, 0.176, 0.768});
  p.fields.set("eta_x", vec({0.015, 0.035, 0.016, 0.064}));
  p.fields.set("eta_u", vec({0.2}));
  p.tube.w = vec({0, 0.05, 0, 0});
  p.input_bounds = {vec({-7}), vec({7})};
  p.state_bounds = {vec({-0.195, -1.99, 1.20, -5.44}), vec({5.49, 4.37, 4.68, 5.28})};
  // Moves the cart about 5 m in 7 s (the slow term) while a force near the pendulum's natural
  // period (about 1.6 s) keeps the load swinging (|theta - pi| up to 0.38 rad, |theta'| up to
  // 1.4 rad/s).
  p.nominal = simulate_nominal(*p.dynamics, vec({0, 0, M_PI, 0}), steps, p.tau, [](int k, const Eigen::VectorXd&) {
    const double t = 0.1 * k;
    return vec({0.62 * std::sin(2 * M_PI * t / 7.0) + 0.5 * std::sin(2 * M_PI * t / 1.4)});
  });
  return p;
}

inline TrackingProblem vehicle() {
  TrackingProblem p;
  p.agent = "vehicle";
  p.dynamics = std::make_shared<models::DoubleIntegrator>();
  p.tube.eps = vec({0.08, 0.12});
  p.fields.set("eta_x", vec({0.01, 0.015}));
  p.fields.set("eta_u", vec({0.1}));
  p.tube.w = vec({0, 0.1});
  p.input_bounds = {vec({-3}), vec({3})};
  p.state_bounds = {vec({3, -3}), vec({9, 1.995})};
  p.nominal = simulate_nominal(*p.dynamics, vec({8, 0}), 70, p.tau, [](int k, const Eigen::VectorXd&) {
    return vec({-0.5 * std::sin(2 * M_PI * 0.1 * k / 7.0)});
  });
  return p;
}

// Swing-up by energy pumping (a dynamics-aware "spiral" nominal), parameters chosen here.
inline TrackingProblem pendulum(int steps = 160) {
  TrackingProblem p;
  p.agent = "pendulum";
  p.dynamics = std::make_shared<models::Pendulum>();
  p.tube.eps = vec({0.2, 0.2});
  p.fields.set("eta_x", vec({0.02, 0.02}));
  p.fields.set("eta_u", vec({0.25}));
  p.tube.w = vec({0, 0.01});
  p.input_bounds = {vec({-4}), vec({4})};
  p.state_bounds = {vec({-4, -4}), vec({4, 4})};
  p.nominal = simulate_nominal(*p.dynamics, vec({0, 0}), steps, p.tau, [](int k, const Eigen::VectorXd& x) {
    const double energy = 0.5 * x[1] * x[1] - std::cos(x[0]);
    double u = 3.0 * (1.0 - energy) * (x[1] >= 0 ? 1.0 : -1.0) + (k == 0 ? 3.0 : 0.0);
    return vec({std::max(-3.0, std::min(3.0, u))});
  });
  return p;
}

}  // namespace marsyn::abcd::scenarios
