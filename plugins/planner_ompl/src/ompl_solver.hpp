#pragma once
// Kinodynamic sampling-based planning with OMPL on the product system: the state is the
// product state plus elapsed time (so no path can exceed the horizon), the propagation is the
// RK4 map with step tau and each control held for 1..max_control_steps whole steps (the
// path is then resampled to one control per step), validity is "every
// eps-robust row <= 0 and within the shrunk state bounds", and the goal region is the shrunk
// goal box (with the terminal rows). Only an exact solution counts. The path reaches the goal
// after L <= T steps; the remaining T - L steps hold the state in the goal with a greedy
// one-step regulator, and the whole plan is re-simulated and measured before it is reported.
#include <string>
#include <vector>

#include "marsyn/params.hpp"
#include "marsyn/planner.hpp"

namespace marsyn::ompl_planner {

struct Options {
  std::string planner = "sst";  // sst | rrt | kpiece1
  double time_limit_s = 30.0;   // planning time (the run's own limit also applies)
  double goal_bias = 0.05;
  double time_weight = 0.1;     // scale of the time coordinate in OMPL's distance (per second)
  double selection_radius = 0.2;  // SST
  double pruning_radius = 0.1;    // SST
  long seed = -1;               // OMPL's process-wide RNG seed; -1 leaves it random
  int max_control_steps = 10;   // longest hold of one sampled control, in steps of tau
  int hold_candidates = 400;    // controls tried per step by the goal-holding regulator
  double feasibility_tolerance = 1e-9;

  // The parameters, declared once in options.cpp (defaults: the initializers above).
  static std::vector<ParamSpec> specs();
  static Options from(const Params& p);  // throws ParamError
};

PlanResult solve(const PlanningProblem& problem, const PlanOptions& run, const Options& options);

}  // namespace marsyn::ompl_planner
