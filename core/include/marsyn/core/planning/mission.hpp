#pragma once
// Missions (docs/tasks.md): each agent's stages, visited in order before its goal. One schedule
// of visit knots per horizon, read by the assembly (constraints at those knots), the exact
// robust check, the certifier and the spec monitor, so that all four judge the same visits.
#include <memory>
#include <string>
#include <vector>

#include "marsyn/constraint.hpp"
#include "marsyn/problem.hpp"

namespace marsyn::planning {

// "stage pickup of r1": the name of the stage's constraint, its requirement in the checks and
// its key in AssemblyOptions::extra.
std::string stage_name(const AgentSpec& agent, int stage);

// The visit knots of a plan ([agent][stage]) at its horizon. They are part of the plan
// (PlanOutcome::visits, plan.json's "visits"): the assembly, the exact check, the certifier, the
// spec monitor, the report and result.json all judge the stages at these knots.
struct MissionSchedule {
  std::vector<std::vector<int>> visit;
  int horizon = 0;
  bool feasible = true;
  std::string why;
  bool empty() const { return visit.empty(); }
};

// The initial guess at horizon T: cumulative straight-line length through the regions' centres
// (workspace points from x0 to the goal), the horizon less the dwells shared in proportion, then
// placed (below). `feasible` is false (with `why`) when no knots meet every window and the order
// at this horizon; the knots are then the nearest ones found.
//
// Placing: each knot moved into its stage's window, after the previous stage's dwell, before the
// next stage, and ending by T - 1; team stages (same `team`) take the latest of their members'
// knots, within every member's window, and every member is placed again with that knot fixed. A
// user-fixed knot (not_before == by) therefore never moves, and a team keeps one knot.
MissionSchedule schedule_missions(const Problem& problem, int horizon);

// The knots re-timed along a trajectory (product states x_0..x_T at horizon T = x.size() - 1):
// per agent, the knot where the trajectory passes deepest through each stage's region (over the
// dwell; each stage searched after the previous one's), its arc length along the agent's
// workspace path as the fraction of the whole, the horizon less the dwells shared by those
// fractions (the same path at an even pace), then placed as above. An agent that does not move
// keeps `current`'s knots.
MissionSchedule retime_missions(const Problem& problem, const MissionSchedule& current,
                                const std::vector<Eigen::VectorXd>& x);

// Whether `s` can be a plan's schedule at horizon T: one knot per stage, in order after the
// dwells, in the windows, the last dwell before T, teams at one knot. Empty string: yes;
// otherwise why not ("stage 'b' of car: knot 12 ...").
std::string schedule_error(const Problem& problem, const MissionSchedule& s, int horizon);

// The problem with every stage's window narrowed to its knot in `s` (not_before = by = knot), so
// that schedule_missions of the result at s.horizon is `s` itself: the mission a plan with these
// knots is tracked, certified and verified against (meeting it meets the original windows).
// When `s` is no schedule at s.horizon (schedule_error: the knots of a failed plan that met no
// window, or none at all), and for a problem without stages, the problem as it is.
Problem with_visits(const Problem& problem, const MissionSchedule& s);

// The schedule a plan of horizon T is judged at: `s` when it is one at T, else the initial one.
MissionSchedule schedule_or_initial(const Problem& problem, const MissionSchedule& s, int horizon);

// The fastest leg of an agent's mission at schedule `s`: straight lines from the start's workspace
// point through the stages' region centres to the goal's (x-y, the larger coordinate), each over
// the knots between its ends (after the previous stage's dwell), in distance per second. A team
// stage fixes when an agent arrives, so one leg can be much faster than the whole path's average
// (the rendezvous: a robot that waits for the others, then crosses the room). 0 without stages.
double fastest_leg_speed(const AgentSpec& agent, const std::vector<int>& visits, int horizon, double tau);

// A sound lower bound (rounding included) of how deep every state of the box `state` (whose
// workspace points lie in `workspace`, 2 coordinates) lies inside the stage's region: >= 0
// implies all of them are inside. Box regions read the state box, polygons the workspace box.
double stage_margin(const MissionStage& stage, const Box& state, const Box& workspace);
// The same over raw bounds (the state's n, the workspace's first 2 coordinates read): the spec
// monitor asks at every substep of every run, without building boxes.
double stage_margin(const MissionStage& stage, const double* state_lo, const double* state_hi, const double* ws_lo,
                    const double* ws_hi);

// The workspace box of a state box for a linear workspace map (outward rounding).
Box linear_workspace_box(const Workspace& ws, const Box& state);

// A stage's region at its visit knots, shrunk by the agent's eps box (+ `clearance`), on the
// product state: box regions one row per bound tighter than the state bounds, polygons (linear
// workspace) one row per edge, n_e . p + |n_e| . (eps of p) + clearance - b_e <= 0.
class StageConstraint final : public Constraint {
 public:
  StageConstraint(std::string name, const AgentSpec& agent, int offset, int stage, std::vector<int> steps,
                  double clearance);
  std::string name() const override { return name_; }
  int size() const override { return static_cast<int>(rows_.size()); }
  ConstraintStage stage() const override { return ConstraintStage::AtSteps; }
  const std::vector<int>& support() const override { return support_; }
  const std::vector<int>& steps() const override { return steps_; }
  void evaluate(const double* x, double* g, double* jac) const override;
  bool hessian(const double*, const double*, double*) const override { return true; }  // linear

 private:
  struct Row {  // sum_t a[t] x[support_[col[t]]] - bound <= 0, over the t with col[t] >= 0
    int col[2];
    double a[2];
    double bound;
  };
  std::string name_;
  std::vector<int> support_, steps_;
  std::vector<Row> rows_;
};

// Stage s of agent a as a waypoint hint (PlanningProblem::waypoints) in a product state of
// dimension n, agent a at `offset`: the region's centre in the coordinates it constrains, NaN
// elsewhere.
Eigen::VectorXd stage_waypoint(const AgentSpec& a, int s, int offset, int n);

// One stage's verdict on a trajectory or on enclosures: its visit knot and the smallest margin
// over its dwell, at the knots and (continuous time) between them.
struct StageVisit {
  int agent = 0, stage = 0;
  std::string name;  // stage_name()
  int step = -1;     // the visit knot
  int dwell = 0;
  // The agent stays in the region over period k (between knots k and k + 1).
  bool dwells_over(int k) const { return k >= step && k < step + dwell; }
  double margin = 0.0;          // min of the two below
  double sampled_margin = 0.0;  // at the knots step..step + dwell
  double between_margin = 1e300;  // between them (continuous guarantee, dwell > 0); 1e300: not checked
};

// When a requirement is judged: at knot k, or over the period [k tau, (k + 1) tau] between it and
// the next knot (between the samples).
struct Moment {
  int k = 0;
  bool between = false;
};

// Staged obstacles (Obstacle::staged, docs/tasks.md "Obstacles of one stage"): for every agent and
// obstacle, the knots where the obstacle binds the agent, from the stages that name it and their
// scheduled knots at one horizon. Stage s's leg runs from the previous stage's last dwell knot (or
// step 0) to its own last dwell knot; `avoid` binds there, `avoid_after` from that last knot to T.
// Over a period the obstacle binds when it binds at both of its knots. An obstacle without
// `scope: stages` binds every agent at every moment. The assembly, the robust check, the
// certifier and the spec monitor all read this one object, so they judge the same windows.
class ObstacleWindows {
 public:
  ObstacleWindows() = default;  // no staged obstacle: everything binds always
  ObstacleWindows(const Problem& problem, int horizon);  // at the initial schedule
  ObstacleWindows(const Problem& problem, const MissionSchedule& visits);
  bool any() const { return !knots_.empty(); }
  bool binds(int agent, int obstacle, Moment m) const {
    if (knots_.empty()) return true;
    const std::vector<char>& on = knots_[static_cast<std::size_t>(agent * obstacles_ + obstacle)];
    if (on.empty()) return true;  // not staged
    const int T = static_cast<int>(on.size()) - 1;
    if (m.k < 0 || m.k > T || !on[static_cast<std::size_t>(m.k)]) return false;
    return !m.between || (m.k < T && on[static_cast<std::size_t>(m.k + 1)]);
  }
  // The knots 1..T where a staged obstacle binds the agent (the planning constraint's AtSteps).
  std::vector<int> knots(int agent, int obstacle) const;
  // "steps 12-40, 55-80" (empty when it never binds), for messages and the report.
  std::string describe(int agent, int obstacle) const;

 private:
  int obstacles_ = 0;
  std::vector<std::vector<char>> knots_;  // [agent * obstacles + o]: per knot 0..T; empty: not staged
};

// Every stage of every agent with its knot in `visits`, margins not yet set.
std::vector<StageVisit> stage_visits(const Problem& problem, const MissionSchedule& visits);
// The same at the initial schedule (schedule_missions at horizon T).
std::vector<StageVisit> stage_visits(const Problem& problem, int horizon);

}  // namespace marsyn::planning
