#pragma once
// Small problems the planner plugins are tested on, built in code: the pendulum swing-up of
// examples/pendulum.yaml and two unicycles swapping sides (they must pass each other).
#include <cmath>
#include <memory>

#include "dynamics_pendulum/src/pendulum.hpp"
#include "dynamics_unicycle/src/unicycle.hpp"
#include "marsyn/problem.hpp"

namespace marsyn::testproblems {

inline Problem pendulum_problem(int horizon = 100) {
  Problem p;
  p.name = "pendulum";
  AgentSpec a;
  a.name = "pendulum";
  a.dynamics_type = "pendulum";
  a.dynamics = std::make_shared<models::Pendulum>();
  a.x0 = Eigen::Vector2d(0, 0);
  a.goal = {Eigen::Vector2d(M_PI - 0.3, -0.3), Eigen::Vector2d(M_PI + 0.3, 0.3)};
  a.state_bounds = {Eigen::Vector2d(-2.5, -3), Eigen::Vector2d(4.5, 3)};
  a.input_bounds = {Eigen::VectorXd::Constant(1, -3), Eigen::VectorXd::Constant(1, 3)};
  a.tube.w = Eigen::Vector2d(0, 0.01);
  a.tube.eps = Eigen::Vector2d(0.2, 0.2);
  a.workspace.index = {0, 1};
  p.agents.push_back(a);
  p.pairwise_collision = false;
  p.tau = 0.1;
  p.horizon = horizon;
  return p;
}

// Two unicycles exchanging ends of a corridor, with a box in the middle of the field.
inline Problem unicycle_crossing(int horizon = 60, bool obstacle = false) {
  Problem p;
  p.name = "unicycle-crossing";
  auto uni = std::make_shared<models::Unicycle>();
  auto make = [&](const std::string& name, Eigen::Vector3d x0, Eigen::Vector3d goal) {
    AgentSpec a;
    a.name = name;
    a.dynamics_type = "unicycle";
    a.dynamics = uni;
    a.x0 = x0;
    a.state_bounds = {Eigen::Vector3d(-1, -3, -2 * M_PI), Eigen::Vector3d(7, 3, 2 * M_PI)};
    a.input_bounds = {Eigen::Vector2d(-2, -2), Eigen::Vector2d(2, 2)};
    const Eigen::Vector3d r(0.4, 0.4, 10.0);
    a.goal = {goal - r, goal + r};
    a.tube.eps = Eigen::Vector3d(0.1, 0.1, 0.1);
    a.tube.w = Eigen::Vector3d(0, 0.01, 0.01);
    a.workspace.index = {0, 1};
    return a;
  };
  p.agents.push_back(make("left", {0, 0, 0}, {6, 0, 0}));
  p.agents.push_back(make("right", {6, 0.1, M_PI}, {0, 0.1, M_PI}));
  if (obstacle) {
    Obstacle o;
    o.name = "box";
    o.vertices = {{2.7, 1.2}, {3.3, 1.2}, {3.3, 1.8}, {2.7, 1.8}};
    o.is_box = true;
    p.obstacles.push_back(o);
  }
  p.delta = 0.3;
  p.delta_norm = Norm::Inf;
  p.tau = 0.1;
  p.horizon = horizon;
  return p;
}

// One unicycle driving past a box in its way.
inline Problem unicycle_obstacle(int horizon = 60) {
  Problem p = unicycle_crossing(horizon);
  p.agents.resize(1);
  Obstacle o;
  o.name = "box";
  o.vertices = {{2.5, -0.5}, {3.5, -0.5}, {3.5, 0.5}, {2.5, 0.5}};
  o.is_box = true;
  p.obstacles = {o};
  return p;
}

// A mission (docs/tasks.md): one unicycle from (0, 0) to (6, 0) that must first visit a square
// above its straight line, around (3, 1.5), then one below it, around (4.5, -1.5). A planner that
// ignores the stages' knots (ConstraintStage::AtSteps) drives straight and fails the check; one
// that imposes them at every knot finds no plan.
inline Problem unicycle_mission(int horizon = 60) {
  Problem p = unicycle_crossing(horizon);
  p.name = "unicycle-mission";
  p.agents.resize(1);
  MissionStage up, down;
  up.name = "up";
  up.polygon = {{2.6, 1.1}, {3.4, 1.1}, {3.4, 1.9}, {2.6, 1.9}};
  down.name = "down";
  down.polygon = {{4.1, -1.9}, {4.9, -1.9}, {4.9, -1.1}, {4.1, -1.1}};
  p.agents[0].stages = {up, down};
  return p;
}

}  // namespace marsyn::testproblems
