#pragma once
// Step 1 of the method: a disturbance-free plan of the product system satisfying the eps-robust
// specification. A Planner is an immutable model; solve() is const and keeps all its scratch
// data inside the call, so one instance may serve several threads.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "marsyn/constraint.hpp"
#include "marsyn/problem.hpp"

namespace marsyn {

enum class PlannerStatus {
  ExactSolution,        // the solver met its tolerances (core still runs the exact robust check)
  ApproximateSolution,  // best effort that violates some constraint
  Infeasible,           // the solver concluded no feasible plan exists at this horizon
  Timeout,
  InvalidInput,
  Crash,
};

inline const char* to_string(PlannerStatus s) {
  switch (s) {
    case PlannerStatus::ExactSolution: return "exact";
    case PlannerStatus::ApproximateSolution: return "approximate";
    case PlannerStatus::Infeasible: return "infeasible";
    case PlannerStatus::Timeout: return "timeout";
    case PlannerStatus::InvalidInput: return "invalid input";
    case PlannerStatus::Crash: return "crash";
  }
  return "?";
}

// A point a plan is asked to pass at knot `step` (a mission stage's region centre at its visit):
// product coordinates, NaN where the stage leaves a coordinate free. A hint for initial guesses
// only; the constraints (ConstraintStage::AtSteps) are what a plan must meet.
struct Waypoint {
  int step = 0;
  Eigen::VectorXd x;
  // How firmly a planner that tracks a reference should follow it: its tracking weight on the
  // coordinates this waypoint pins is multiplied by this (at least 1). A route around obstacles
  // (core's plan search) asks for more than a mission stage, whose constraints already hold it.
  double follow = 1.0;
};

// The eps-robust planning problem on the product system, assembled by core from a Problem.
struct PlanningProblem {
  const Problem* problem = nullptr;  // agents and their dynamics (product = stacked agents)
  Eigen::VectorXd x0;                // product initial state
  Box input_bounds;                  // U^x
  Box state_bounds;                  // X^x shrunk by eps
  Box goal;                          // Goal^x shrunk by eps (terminal state)
  std::vector<std::shared_ptr<const Constraint>> constraints;  // avoid set grown by eps
  // Continuous time: the requirements again, on the flow between the samples. Each constraint
  // here (stage AllSteps, on the product state) must also hold at the interior points
  // x_{k,j}, j = 1..between_points, of every period k = 0..T-1: the
  // disturbance-free flow from x_k under u_k after the fraction j / (between_points + 1) of tau
  // (flow_point in sampled_map.hpp). They are functions of (x_k, u_k), so planners differentiate them through
  // the partial RK4 step. Empty (or between_points == 0) under the sampled guarantee.
  std::vector<std::shared_ptr<const Constraint>> between;
  int between_points = 0;
  int horizon = 0;
  std::optional<GlobalPlan> warm_start;
  std::vector<Waypoint> waypoints;  // mission stages' visits, ordered by step (empty without stages)
};

struct PlanProgress {
  int iteration = 0;
  double cost = 0.0;
  double max_violation = 0.0;
};

struct PlanOptions {
  double time_limit_s = 60.0;
  std::function<void(const PlanProgress&)> progress;  // may be empty
};

struct PlanResult {
  PlannerStatus status = PlannerStatus::Crash;
  GlobalPlan plan;
  int iterations = 0;
  double solve_time_s = 0.0;
  double max_violation = 0.0;  // the solver's own measure; core re-checks exactly
  double cost = 0.0;
  std::string message;
};

// What a planner holds while solving a problem over its horizon, for the loader's check against
// the run's memory budget: bytes, and how they are made up (for the message).
struct PlannerMemory {
  double bytes = 0;
  std::string detail;
};

class Planner {
 public:
  virtual ~Planner() = default;
  virtual std::string name() const = 0;
  virtual PlanResult solve(const PlanningProblem& problem, const PlanOptions& options) const = 0;
  // The planner's own figure for `problem` at problem.horizon. Empty: core's conservative one
  // (every pair's and obstacle's rows with their gradients at every step, as a dense NLP holds).
  virtual std::optional<PlannerMemory> memory(const Problem&) const { return std::nullopt; }
};

}  // namespace marsyn
