#pragma once
// Evaluates the *real* global specification (paper eq. 2 and 3, no eps) on simulated product
// states: goals reached at the final step, obstacles and other agents at least delta away,
// formation distances within lambda +- mu. Margins are signed: >= 0 satisfied, < 0 violated.
// The requirements and their formulas are spec_margins.hpp's, the robust check's with no margin.
#include <algorithm>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "marsyn/core/planning/geometry.hpp"
#include "marsyn/core/planning/mission.hpp"
#include "marsyn/problem.hpp"

namespace marsyn {

// The real specification's distances are the one geometry module's (planning/geometry.hpp).
using planning::signed_distance_inf;
using planning::signed_distance_two;

struct StepMargins {
  double obstacle = 1e300;   // min over agents and obstacles of d - delta
  double collision = 1e300;  // min over pairs of d - delta
  double formation = 1e300;  // min over formation pairs of mu - |d - lambda|
  double stage = 1e300;      // mission stages (docs/tasks.md) dwelling at this time: depth inside the region
  double min() const { return std::min({obstacle, collision, formation, stage}); }
};

struct SpecEvaluation {
  bool satisfied = true;
  double min_margin = 1e300;
  std::string worst;  // e.g. "collision drone1 vs drone4 at step 37"
  std::vector<StepMargins> per_step;
  double goal_margin = 1e300;  // min over agents and coordinates at the final step
};

class SpecMonitor {
 public:
  // horizon >= 0: the mission stages' visit knots at that horizon (planning::schedule_missions),
  // for the closed loop's per-sample calls below; evaluate() schedules at its states' horizon.
  explicit SpecMonitor(const Problem& problem, int horizon = -1);
  // states[k] is the product state at step k (agents stacked in problem order).
  SpecEvaluation evaluate(const std::vector<Eigen::VectorXd>& states, bool keep_per_step = false) const;
  // The requirements at one product state. `when` (k >= 0) applies the staged obstacles' windows
  // (planning::ObstacleWindows at this monitor's horizon): at knot k, or between k and k + 1;
  // k < 0: every obstacle binds (a state without a time).
  StepMargins step(const Eigen::VectorXd& x, std::string* worst = nullptr, planning::Moment when = {-1, false}) const;
  // evaluate()'s goal part: the final state x's goal margins folded into ev (min_margin, worst,
  // goal_margin), for a caller that checked the samples as they came.
  void add_goal(const Eigen::VectorXd& x, SpecEvaluation& ev) const;
  // Mission stages at sample k (the stages whose visit knots include k): each agent's state in
  // the region, folded into ev (min_margin, worst) like the goal.
  void add_stages(int k, const Eigen::VectorXd& x, SpecEvaluation& ev) const;
  // Between samples k and k + 1 (continuous guarantee): the stages dwelling over that period.
  // Returns the smallest depth (1e300: none dwells) and names the stage.
  double stage_between(int k, const Eigen::VectorXd& x, std::string* name) const;
  bool has_stages() const { return !visits_.empty(); }
  const planning::ObstacleWindows& windows() const { return windows_; }
  // The stages' visits at this monitor's horizon (stage_between's order), and one visit's depth
  // for its agent's state xi (n coordinates) and workspace point p: stage_between's terms, for a
  // caller that holds the agents' states and points apart.
  const std::vector<planning::StageVisit>& visits() const { return visits_; }
  double stage_depth(const planning::StageVisit& v, const double* xi, const planning::Point& p) const;
  // Whether visit v's depth at p (a polygon stage's) is certainly above `value`: a plain estimate
  // (the smallest distance inside the edges' lines) clears it by a slack far above both its
  // rounding and stage_depth's interval width (a few ulps of the coordinates), so stage_depth
  // would too. False for box stages (a few subtractions: always evaluated) and for NaN.
  bool stage_clears(int v, const planning::Point& p, double value) const;

 private:
  void points(const Eigen::VectorXd& x, std::vector<planning::Point>& p) const;  // the agents' workspace points
  double stage_depth(const planning::StageVisit& v, const Eigen::VectorXd& x) const;
  const Problem& problem_;
  std::vector<int> offset_;
  std::vector<planning::StageVisit> visits_;
  std::vector<planning::PolygonEdges> stage_edges_;  // per visit: its polygon's edges (none for a box stage)
  std::vector<double> stage_scale_;                  // per visit: the polygon's largest coordinate
  planning::ObstacleWindows windows_;
};

}  // namespace marsyn
