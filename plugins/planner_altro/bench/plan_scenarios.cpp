#include "plan_scenarios.hpp"

#include <cmath>
#include <stdexcept>

#include "dynamics_cartpole/src/cartpole.hpp"
#include "dynamics_double_integrator/src/double_integrator.hpp"
#include "dynamics_pendulum/src/pendulum.hpp"
#include "dynamics_unicycle/src/unicycle.hpp"

namespace marsyn::bench {

namespace {

using V = Eigen::VectorXd;

V vec(std::initializer_list<double> v) {
  V r(static_cast<int>(v.size()));
  int i = 0;
  for (double x : v) r[i++] = x;
  return r;
}

Box around(const V& centre, const V& radius) { return {centre - radius, centre + radius}; }

AgentSpec agent(std::string name, std::shared_ptr<const Dynamics> dyn, V x0, Box X, Box U, V eps, V w) {
  AgentSpec a;
  a.name = std::move(name);
  a.dynamics_type = dyn->type();
  a.dynamics = std::move(dyn);
  a.x0 = std::move(x0);
  a.state_bounds = std::move(X);
  a.input_bounds = std::move(U);
  a.tube.eps = std::move(eps);
  a.tube.w = std::move(w);
  return a;
}

Obstacle polygon(std::string name, std::vector<Eigen::Vector2d> v) {
  Obstacle o;
  o.name = std::move(name);
  o.vertices = std::move(v);
  return o;
}

Obstacle square(std::string name, double cx, double cy, double half) {
  auto o = polygon(std::move(name), {{cx - half, cy - half}, {cx + half, cy - half}, {cx + half, cy + half}, {cx - half, cy + half}});
  o.is_box = true;
  return o;
}

Scenario drones() {
  Scenario s{"multi-drone-10", {}, {}};
  auto& p = s.problem;
  p.name = s.name;
  auto uni = std::make_shared<models::Unicycle>();
  const V eps = vec({0.20, 0.20, 0.24}), radius = vec({0.3, 0.3, 0.4});
  const Box X{vec({-1, -1, -2}), vec({11, 11, 3.3})}, U{vec({-2.4, -2.4}), vec({2.4, 2.4})};
  std::vector<std::pair<V, V>> sg;
  for (double y : {2, 4, 6, 8}) sg.push_back({vec({0, y, 0}), vec({10, y, 0})});
  for (double x : {2, 4, 6, 8}) sg.push_back({vec({x, 0, M_PI / 2}), vec({x, 10, M_PI / 2})});
  sg.push_back({vec({0, 0, M_PI / 4}), vec({10, 10, M_PI / 4})});
  sg.push_back({vec({0, 10, -M_PI / 4}), vec({10, 0, -M_PI / 4})});
  for (size_t i = 0; i < sg.size(); ++i) {
    auto a = agent("drone" + std::to_string(i + 1), uni, sg[i].first, X, U, eps, vec({0, 0.025, 0.025}));
    a.goal = around(sg[i].second, radius);
    p.agents.push_back(a);
  }
  p.obstacles.push_back(square("block", 5, 5, 1));
  p.delta = 0.24;
  p.delta_norm = Norm::Inf;
  p.tau = 0.1;
  p.horizon = 104;
  return s;
}

Scenario crane_vehicle() {
  Scenario s{"crane-vehicle", {}, {}};
  auto& p = s.problem;
  p.name = s.name;
  auto crane = std::make_shared<models::CartPole>();
  const V ce = vec({0.135, 0.385, 0.176, 0.768});
  auto c = agent("crane", crane, vec({0, 0, M_PI, 0}), {vec({-0.195, -1.99, 1.20, -5.44}), vec({5.49, 4.37, 4.68, 5.28})},
                 {vec({-7}), vec({7})}, ce, vec({0, 0.05, 0, 0}));
  c.goal = around(vec({5, 0, M_PI, 0}), vec({0.25, 0.6, 0.3, 1.2}));
  c.workspace.footprint = 0;
  c.workspace.footprint_name = "pendulum_tip";
  auto vehicle = std::make_shared<models::DoubleIntegrator>();
  const V ve = vec({0.08, 0.12});
  auto v = agent("vehicle", vehicle, vec({8, 0}), {vec({3, -3}), vec({9, 1.995})}, {vec({-3}), vec({3})}, ve, vec({0, 0.1}));
  v.goal = around(vec({4, 0}), vec({0.3, 0.4}));
  v.workspace.index = {0, -1};
  v.workspace.offset = {0.0, 0.2};
  p.agents = {c, v};
  // The paper's delta (0.035). With the reference code's 0.35 and these eps the tip would have to pass
  // over the vehicle above the horizontal, theta in [1.376, 1.49], see docs/benchmarks-altro.md.
  p.delta = 0.035;
  p.delta_norm = Norm::Inf;
  p.tau = 0.1;
  p.horizon = 70;
  return s;
}

Scenario lane_merging() {
  Scenario s{"lane-merging-6", {}, {}};
  auto& p = s.problem;
  p.name = s.name;
  auto uni = std::make_shared<models::Unicycle>();
  const V eps = vec({0.16, 0.16, 0.16});
  const Box X{vec({-0.5, 0.1, -1}), vec({20, 7.4, 0.4})}, U{vec({-0.9, -2.1}), vec({3, 2.1})};
  const Box G{vec({15, 0.1, -0.5}), vec({20, 2.4, 0.4})};  // past the line x = 15, in the main lane
  const std::vector<V> starts = {vec({6, 1.2, 0}), vec({3, 1.2, 0}), vec({0, 1.2, 0}),
                                 vec({8, 3.9, -0.64}), vec({6, 5.4, -0.64}), vec({4, 6.9, -0.64})};
  const char* names[] = {"main1", "main2", "main3", "ramp1", "ramp2", "ramp3"};
  for (size_t i = 0; i < starts.size(); ++i) {
    auto a = agent(names[i], uni, starts[i], X, U, eps, vec({0.03, 0.03, 0.03}));
    a.goal = G;
    p.agents.push_back(a);
  }
  // The road: main lane y in [0, 2.4]; the ramp between the lines 3x + 4y = 33.6 and 45.6; the
  // lane's upper edge exists for x < 8 and x > 12.
  p.obstacles.push_back(square("road_bottom", 10, -0.5, 0.5));
  p.obstacles.back().vertices = {{-1, -1}, {21, -1}, {21, 0}, {-1, 0}};
  p.obstacles.push_back(polygon("ramp_inner", {{-1, 2.4}, {8, 2.4}, {-1, 9.15}}));
  p.obstacles.push_back(polygon("ramp_outer", {{12, 2.4}, {21, 2.4}, {21, 8}, {4.5333333333, 8}}));
  p.delta = 0.37;
  p.delta_norm = Norm::Two;
  p.tau = 0.1;
  p.horizon = 110;
  return s;
}

Scenario formation() {
  Scenario s{"formation-5", {}, {}};
  auto& p = s.problem;
  p.name = s.name;
  auto uni = std::make_shared<models::Unicycle>();
  // As examples/formation.yaml: position eps 0.12 instead of 0.24 (the band mu = 0.5 must absorb
  // both agents' Euclidean margins; 2 * 0.24 * sqrt 2 = 0.68 would leave no sound formation).
  // Heading bounds from -0.4, not 0.5: with headings in [0.74, 1.36] (after eps) the formation
  // can only cross the 2.44 m corridor between the obstacles, or pass around them, by reversing
  // zig-zags (no plan found up to T = 197); from 0.0 it needs T = 125 (docs/benchmarks-altro.md).
  const V eps = vec({0.12, 0.12, 0.24}), radius = vec({0.4, 0.4, 0.5});
  const Box X{vec({-2, -2, -0.4}), vec({17, 17, 1.6})}, U{vec({-0.9, -3}), vec({4.8, 3})};
  const std::vector<Eigen::Vector2d> off = {{0, 0}, {0, 1.5}, {1.5, 0}, {0, -1.5}, {-1.5, 0}};
  const char* names[] = {"centre", "north", "east", "south", "west"};
  for (size_t i = 0; i < off.size(); ++i) {
    auto a = agent(names[i], uni, vec({off[i].x(), off[i].y(), M_PI / 4}), X, U, eps,
                   vec({0.03, 0.03, 0.03}));
    a.goal = around(vec({15 + off[i].x(), 15 + off[i].y(), M_PI / 4}), radius);
    p.agents.push_back(a);
  }
  for (size_t i = 0; i < off.size(); ++i)
    for (size_t j = i + 1; j < off.size(); ++j)
      p.formation.push_back({static_cast<int>(i), static_cast<int>(j), (off[i] - off[j]).norm(), 0.5});
  p.obstacles.push_back(square("upper", 7, 11.5, 2.26));
  p.obstacles.push_back(square("lower", 7, 3.5, 2.26));
  p.delta = 0.4;
  p.delta_norm = Norm::Inf;
  p.tau = 0.1;
  p.horizon = 100;
  return s;
}

Scenario pendulum() {
  Scenario s{"pendulum-swing-up", {}, {}};
  auto& p = s.problem;
  p.name = s.name;
  auto pend = std::make_shared<models::Pendulum>();
  // As examples/pendulum.yaml (the paper gives no bounds).
  const V eps = vec({0.2, 0.2});
  auto a = agent("pendulum", pend, vec({0, 0}), {vec({-2.5, -3}), vec({4.5, 3})}, {vec({-3}), vec({3})}, eps,
                 vec({0, 0.01}));
  a.goal = around(vec({M_PI, 0}), vec({0.3, 0.3}));
  a.workspace.index = {0, 1};  // the phase plane; no obstacles or partners use it
  p.agents.push_back(a);
  p.pairwise_collision = false;
  p.tau = 0.1;
  p.horizon = 100;
  return s;
}

Scenario swap50() {
  Scenario s{"swap-50", {}, {}};
  auto& p = s.problem;
  p.name = s.name;
  auto uni = std::make_shared<models::Unicycle>();
  const int N = 50;
  const double R = 12.0;
  const V eps = vec({0.1, 0.1, 0.1}), radius = vec({0.3, 0.3, 0.3});
  const Box X{vec({-14, -14, -10}), vec({14, 14, 10})}, U{vec({-3, -2}), vec({3, 2})};
  for (int i = 0; i < N; ++i) {
    const double phi = 2 * M_PI * i / N;
    const V x0 = vec({R * std::cos(phi), R * std::sin(phi), phi + M_PI});
    auto a = agent("u" + std::to_string(i), uni, x0, X, U, eps, vec({0.02, 0.02, 0.02}));
    a.goal = around(vec({-x0[0], -x0[1], phi + M_PI}), radius);
    p.agents.push_back(a);
  }
  p.delta = 0.2;
  p.delta_norm = Norm::Inf;
  p.tau = 0.1;
  p.horizon = 150;
  s.planner_params.set("bend", 0.25);
  return s;
}

}  // namespace

std::vector<std::string> scenario_names() {
  return {"multi-drone-10", "crane-vehicle", "lane-merging-6", "formation-5", "pendulum-swing-up", "swap-50"};
}

Scenario make_scenario(const std::string& name) {
  if (name == "multi-drone-10") return drones();
  if (name == "crane-vehicle") return crane_vehicle();
  if (name == "crane-vehicle-delta-0.35") {  // the reference code's delta; not in the default list
    auto s = crane_vehicle();
    s.name = name;
    s.problem.name = name;
    s.problem.delta = 0.35;
    return s;
  }
  if (name == "lane-merging-6") return lane_merging();
  if (name == "formation-5") return formation();
  if (name == "pendulum-swing-up") return pendulum();
  if (name == "swap-50") return swap50();
  throw std::invalid_argument("unknown scenario " + name);
}

}  // namespace marsyn::bench
