#pragma once
// Augmented-Lagrangian iLQR on the product system, in the spirit of ALTRO (Howell et al. 2019):
// iLQR inner solves on the RK4 map with exact AD Jacobians, outer multiplier/penalty updates,
// Levenberg-Marquardt style regularization and a backtracking line search. The product dynamics
// are block diagonal; the backward pass works on groups of agents (all agents in one group:
// exact Gauss-Newton; one agent per group: a block-diagonal Gauss-Newton majorizer whose cost
// grows linearly in the number of agents). See docs/planning.md.
#include <string>
#include <vector>

#include "marsyn/params.hpp"
#include "marsyn/planner.hpp"

namespace marsyn::altro {

struct Options {
  int max_iterations = 3000;        // iLQR iterations in total
  int max_outer = 30;               // augmented-Lagrangian updates
  int max_inner = 150;              // iLQR iterations per outer update
  double cost_tolerance = 1e-5;     // relative cost decrease ending an inner solve once feasible
  double cost_tolerance_intermediate = 1e-3;  // ... while still infeasible
  double constraint_tolerance = 1e-6;         // max violation of the (buffered) constraints
  double penalty_initial = 1.0;
  double penalty_scaling = 10.0;
  double penalty_max = 1e8;
  double reg_initial = 1e-4;
  double reg_min = 1e-8;
  double reg_max = 1e10;
  double reg_factor = 4.0;
  double small_step = 0.125;        // accepted steps at most this long raise the regularization
  int line_search_steps = 12;
  double q_track = 0.05;            // weight of the straight-line reference per state coordinate
  double r_input = 0.3;             // input weight
  double q_terminal = 10.0;         // terminal weight towards the goal centre
  // Per product-state coordinate factors on q_track (empty: all 1). They let a problem ask for a
  // calm plan, e.g. a crane whose swing angle and rate are kept near the hanging reference except
  // where a constraint forces them away.
  std::vector<double> q_state;
  double bend = 0.1;                // lateral bend of the reference, x path length (breaks symmetry)
  // Teams of 3 or more: when the references cut into pair requirements, try 1.5, 2, 3, 4 x bend
  // and keep the first without a cut (else the shallowest).
  bool bend_search = true;
  int polish_iterations = 10;         // final projection steps onto the active constraints
  double polish_start = 1e-1;          // tried before more penalty rounds below this violation
  double polish_max_violation = 1e-2;  // after the last round, attempted only below this violation
  int polish_active_rounds = 20;      // solves per projection step (inequality_step.hpp)
  double polish_max_work = 3e9;        // ... and when J J' (summed agent by agent) is this small
  std::string coupling = "auto";    // exact | block | auto
  int exact_max_states = 60;        // auto: exact coupling up to this many product states
  // Skip the pair rows whose agents are farther apart than the rows' reach (Constraint::pair_reach)
  // and that carry no multiplier: they add exactly nothing, so the plan is the same bit for bit.
  bool broad_phase = true;
  // Threads for the Jacobians, rollouts, costs and the per-agent backward pass (0: the machine's,
  // at most 8). The plan does not depend on it: per-knot results are reduced in knot order.
  int threads = 0;

  // The parameters, declared once in options.cpp (defaults: the initializers above).
  static std::vector<ParamSpec> specs();
  static Options from(const Params& p);  // throws ParamError
};

PlanResult solve(const PlanningProblem& problem, const PlanOptions& run, const Options& options);

// What solve() holds for `problem` at its horizon (Planner::memory): per step the agents' blocks
// and one multiplier per requirement row (at the samples and at the point between them), and per
// row, once, its constraint objects, the solver's reference to it and the broad phase's entry.
// The rows' gradients are computed where needed and never stored, so a pair costs bytes per
// step, not its Jacobian (measured: `git show f9b6c78:docs/benchmarks.md`, "Large teams: memory
// and time of a plan").
PlannerMemory memory(const Problem& problem);

}  // namespace marsyn::altro
