#pragma once
// What `marsyn plan` runs: assemble the eps-robust problem, solve it with a Planner, clamp and
// re-simulate the inputs, run the exact check, and lengthen the horizon when that fails.
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "marsyn/core/planning/constraints.hpp"
#include "marsyn/core/planning/robust_check.hpp"
#include "marsyn/planner.hpp"

namespace marsyn::planning {

struct PlanSearchOptions {
  AssemblyOptions assembly;
  int max_attempts = 4;          // horizons tried: T, then T * growth, ... (bounded)
  double horizon_growth = 1.25;  // factor between attempts (at least +1 step)
  double time_limit_s = 300.0;   // for the whole search; each solve gets what is left
  std::function<void(const std::string&)> log;        // one line per attempt; may be empty
  std::function<void(const PlanProgress&)> progress;  // forwarded to the planner; may be empty
  // An initial guess for the first attempt (inputs; the search starts at its horizon when that is
  // longer than the problem's). Later attempts start from the previous attempt, as without it.
  std::optional<GlobalPlan> warm_start;
  // A planner chain: this planner's search runs first and its plan (the robust one, else the
  // best attempt's) is the warm start of the main planner, e.g. a global sampler or an interior
  // point method finding the shape, the default planner refining it under its own cost. When the
  // main planner finds no robust plan, a robust plan of the first one is returned instead.
  const Planner* warm_start_planner = nullptr;
  // A plan short at the samples whose agents' straight lines cross obstacles is tried again at
  // the same horizon from routes around them (routes.hpp), once; later horizons keep the routes.
  bool routes = true;
  // Mission stages (docs/tasks.md "What is planned"): how many times the visit knots are
  // re-timed along a plan (retime_missions) at one horizon: after a solve short at a stage,
  // before a longer horizon is tried, and after a robust plan, kept only when the re-solve is
  // robust and of less input effort. 0: the initial schedule (options.assembly.visits when it is
  // one at the first horizon, else schedule_missions) at every horizon.
  int retime_rounds = 3;
  // True once the run should end (a signal, the solve's time limit): no further horizon or
  // re-timing is started; the best attempt so far is returned. May be empty.
  std::function<bool()> stop;
  // Whether a failed search logs the gaps closed at every horizon (a solve of many rounds says
  // them once, not after every failed plan).
  bool log_closed_gaps = true;
};

// The input effort of a plan: sum over knots, agents and inputs of (u / the bound's magnitude)^2
// times tau. The measure re-timings are compared by (every planner's cost has it, not the rest).
double input_effort(const Problem& problem, const GlobalPlan& plan);

// The share (0..1) of the steps on which some input of `u` lies within 1e-6 of U's range of a bound.
double saturation_share(const std::vector<Eigen::VectorXd>& u, const Box& bounds);

struct PlanAttempt {
  std::string planner;  // Planner::name()
  int horizon = 0;
  PlannerStatus status = PlannerStatus::Crash;
  int iterations = 0;
  double solve_time_s = 0.0;
  double max_violation = 0.0;
  RobustCheck check;
  std::string message;
  MissionSchedule visits;  // the knots this attempt was planned and checked at
  double effort = 0.0;     // input_effort of its clamped plan
  bool retimed = false;    // its knots were re-timed along the attempt before it
};

struct PlanOutcome {
  bool feasible = false;  // the exact robust check passed
  int horizon = 0;
  PlanResult result;      // of the returned attempt
  RobustCheck check;      // of the returned plan
  GlobalPlan plan;        // inputs clamped to U, states re-simulated from x0
  // The mission stages' visit knots of `plan` (mission.hpp): part of the plan, written to
  // plan.json, and what every later stage judges the stages at. Empty without a plan.
  MissionSchedule visits;
  std::vector<NominalTrajectory> nominal;  // per agent: the projection of `plan`
  std::vector<PlanAttempt> attempts;  // a warm-start planner's first, then the main planner's
  double total_time_s = 0.0;
  // The per-constraint clearance the returned plan was made with (options.assembly.extra plus
  // what the continuous-time re-plans added), for a later re-plan to start from.
  std::map<std::string, double> extra;
  // Why the search tried no longer horizon, when its policy found that time is not what the
  // failure lacks (a stage pinned at the end of its window, the same shortfall at two horizons):
  // the outer search does not lengthen the horizon either. Empty: not judged so.
  std::string horizon_blocked;
};

// Never throws for algorithmic failure (feasible == false then, with the best attempt's data);
// throws std::invalid_argument for an inconsistent problem.
PlanOutcome plan(const Problem& problem, const Planner& planner, const PlanSearchOptions& options = {});

// A one-screen human summary.
std::string summary(const Problem& problem, const PlanOutcome& outcome);

}  // namespace marsyn::planning
