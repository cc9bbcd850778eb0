#pragma once
// The exact eps-robust check, independent of any solver: re-simulate the nominal inputs from x0
// with the sampled map f_tau and verify, at every step k = 0..T, that every state within eps of
// the nominal one satisfies the real specification (docs/planning.md, "Exact check").
#include <array>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "marsyn/core/planning/mission.hpp"
#include "marsyn/problem.hpp"

namespace marsyn::planning {

// A requirement the continuous nominal misses between the samples: its most negative margin and
// the largest knot-to-knot motion of the workspace points involved (in the problem's norm) over
// the periods where it is missed.
struct BetweenShortfall {
  double margin = 0.0;
  double motion = 0.0;
  bool collision = false;  // a pair of agents' clearance (what a crowd's clearance widens)
};

struct RobustCheck {
  bool passed = false;
  // Smallest signed margin over the state requirements (bounds, goal, obstacles, collisions,
  // formation), and the requirement attaining it, e.g. "collision drone1 vs drone2".
  double min_margin = 0.0;
  std::string worst;
  int worst_step = -1;
  // The agents of the worst requirement when it is a workspace one (an obstacle: {agent, -1};
  // a pair or formation: both), else {-1, -1}: what the plan search changes routes for.
  std::array<int, 2> worst_agents{-1, -1};
  // Inputs are reported apart: clamped inputs sit exactly on their bounds (margin 0).
  double min_input_margin = 0.0;
  std::string worst_input;
  double max_state_mismatch = 0.0;  // |re-simulated x - plan.x|_inf, when the plan carries states
  std::string message;              // one line for humans
  // Continuous time (problem.guarantee == Continuous): the same requirements between the
  // samples, on the eps-box around enclosures (flow_enclosure.hpp, kFlowParts parts of every
  // period, more where that falls short) of the exact disturbance-free flow from x_k under u_k: the continuous nominal.
  // min_margin above is the smaller of the sampled and the between-samples margins.
  bool continuous = false;
  double sampled_margin = 0.0;
  double between_margin = std::numeric_limits<double>::infinity();
  std::string worst_between;
  int worst_between_step = -1;
  // Every requirement with a negative margin between the samples, by constraint name (as in
  // AssemblyOptions::extra), with its most negative margin.
  std::map<std::string, BetweenShortfall> between_shortfalls;
  // Mission stages (docs/tasks.md): each at the plan's knots, the eps-box of the nominal in
  // the region (and, dwelling under the continuous guarantee, the continuous nominal's
  // eps-boxes between those knots). Their margins are part of min_margin above.
  std::vector<StageVisit> stages;
};

inline constexpr int kFlowParts = 8;
// A period short between the samples is checked again with kFlowRefinement times as many parts,
// up to kFlowMaxParts (finer boxes, the same enclosure argument).
inline constexpr int kFlowRefinement = 4;
inline constexpr int kFlowMaxParts = 128;

// x_0 = problem's x0, x_{k+1} = f_tau(x_k, u_k) (RK4, problem.rk4_substeps), no disturbance.
std::vector<Eigen::VectorXd> rollout(const Problem& problem, const std::vector<Eigen::VectorXd>& inputs);

// Re-simulates plan.u and checks the eps-robust spec along the result (plan.x is only compared);
// under the continuous guarantee also between the samples. The mission stages (and the staged
// obstacles' windows) are judged at `visits`, the plan's knots; knots that are no schedule at
// the plan's horizon (schedule_error) fail the check. Without `visits`: the initial schedule.
RobustCheck check_robust(const Problem& problem, const GlobalPlan& plan, const MissionSchedule& visits);
RobustCheck check_robust(const Problem& problem, const GlobalPlan& plan);

// How the check between the samples is carried out; the result does not depend on it.
struct RobustCheckOptions {
  // Each requirement is first judged on its agents' boxes over the whole period, and its parts
  // are skipped where that margin leaves no part able to change the outcome (robust_check.cpp,
  // floor_decides). false: every part of every requirement, the reference the tests compare with.
  bool period_floors = true;
};
RobustCheck check_robust(const Problem& problem, const GlobalPlan& plan, const MissionSchedule& visits,
                         const RobustCheckOptions& options);

}  // namespace marsyn::planning
