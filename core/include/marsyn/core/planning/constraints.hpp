#pragma once
// Assembly of the eps-robust planning problem (paper Sec. 3.1: Avoid grown by eps, Goal shrunk by
// eps) from a Problem: bounds become boxes, workspace requirements become Constraint objects.
// Formulas and the margin argument: docs/planning.md.
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "marsyn/constraint.hpp"
#include "marsyn/core/planning/geometry.hpp"
#include "marsyn/core/planning/margins.hpp"
#include "marsyn/core/planning/spec_margins.hpp"  // the requirements' names
#include "marsyn/planner.hpp"

namespace marsyn::planning {

struct AssemblyOptions {
  // Extra slack every constraint keeps (same units as the constraint), so that a solver answer
  // within its own tolerance, and the input clamping after it, still pass the exact check.
  double buffer = 1e-3;
  // Width c of the smoothed corner of the inf-norm condition between agents, in units of the
  // required distance: a smooth lower bound of max(|dx|/rx, |dy|/ry), exact when the two differ
  // by at least 2c, conservative by at most 4c/27 otherwise (docs/planning.md).
  double inf_norm_corner = 0.3;
  // Continuous time (problem.guarantee == Continuous): interior points of every period at which
  // the requirements are imposed too (PlanningProblem::between), and the extra clearance they
  // keep beyond `buffer`: this fraction of the distance the agent's workspace point covers
  // between two interior points at its estimated speed (workspace_speed_bound over the horizon;
  // a pair or formation takes the larger of its two agents'). A straight chord between two
  // points that clear a convex set can cut into it by up to half its length, and the exact check
  // encloses the flow in boxes. 0 points: the knots only (docs/planning.md, "Between the samples").
  int between_points = 1;
  double between_clearance = 1.0;
  // Extra slack for single constraints, by name ("obstacle <o> vs <agent>", "collision <a> vs
  // <b>", "formation <a> - <b>", "state bound <state name> of <agent>"): where a continuous-time check found
  // the plan (or the trackers' period enclosures) too close between the samples.
  std::map<std::string, double> extra;
  // Extra slack every pair keeps at the interior points (not at the knots): the team-wide
  // answer when several pairs of a crowd came short between the samples at once.
  double pair_between_extra = 0.0;
  // The mission stages' visit knots (the plan's, mission.hpp); empty or of another horizon: the
  // initial schedule at the horizon assembled.
  MissionSchedule visits;
};

// The clearance agent `agent`'s requirements keep at the interior points beyond the buffer
// (AssemblyOptions::between_clearance x spacing x estimated speed, its mission's legs timed by
// `visits`); 0 without interior points.
double between_clearance(const Problem& problem, int agent, const MissionSchedule& visits, int horizon,
                         const AssemblyOptions& options);


// p = workspace point of agent state x; J (2 x n, row-major) = dp/dx when non-null.
void workspace_point_jacobian(const AgentSpec& agent, const double* x, double* p, double* J);

class ObstacleConstraint final : public Constraint {
 public:
  // Keeps the workspace point outside the obstacle grown by the margin box (+ `grow`, delta for
  // the inf-norm) by at least `clearance` in the Euclidean norm.
  // With `distance` (built over the grown obstacle, a collision plugin), the signed distance comes
  // from it; only for constant margins, where the grown polygon is fixed.
  ObstacleConstraint(std::string name, const AgentSpec& agent, int offset, Polygon obstacle,
                     std::shared_ptr<const MarginTable> margins, double grow, double clearance,
                     const DistanceModelFactory& distance = {});
  bool uses_distance_model() const { return distance_ != nullptr; }
  // A 3-D workspace's prism: the obstacle is the polygon times [z_lo, z_hi] (grown as the
  // polygon); unbounded (the default) in the plane. A bounded prism is judged by core's geometry.
  void set_z(double z_lo, double z_hi);
  // A staged obstacle (ObstacleWindows): the knots where it binds, instead of every knot.
  void bind_only_at(std::vector<int> steps) {
    steps_ = std::move(steps);
    only_at_ = true;
  }
  std::string name() const override { return name_; }
  int size() const override { return 1; }
  ConstraintStage stage() const override { return only_at_ ? ConstraintStage::AtSteps : ConstraintStage::AllSteps; }
  const std::vector<int>& support() const override { return support_; }
  const std::vector<int>& steps() const override { return steps_; }
  void evaluate(const double* x, double* g, double* jac) const override;
  bool hessian(const double* x, const double* w, double* H) const override;
  // The grown polygon's bounding box widened by the clearance (and a relative 1e-9 for the
  // distance's rounding): outside it the Euclidean distance exceeds the clearance. Only for a
  // constant margin with core's own distance (a collision plugin's may round otherwise).
  bool clear_outside(double lo[2], double hi[2]) const override;
  // g = clearance - sd with sd the Euclidean distance: a point s beyond that box is at least
  // clearance + s from the polygon (rate 1, less a relative 1e-9 against rounding).
  double reach_decay() const override { return 1.0 - 1e-9; }

 private:
  std::string name_;
  std::vector<int> steps_;
  bool only_at_ = false;
  const AgentSpec* agent_;
  std::vector<int> support_;
  Polygon obstacle_, grown_;  // grown_: precomputed for a constant margin
  PolygonEdges grown_edges_;  // and its edges
  std::shared_ptr<const MarginTable> margins_;
  double grow_, clearance_;
  std::shared_ptr<const DistanceModel> distance_;
  double z_lo_ = -std::numeric_limits<double>::infinity(), z_hi_ = std::numeric_limits<double>::infinity();
  bool prism() const {
    return agent_->workspace.dim() == 3 &&
           (z_lo_ > -std::numeric_limits<double>::infinity() || z_hi_ < std::numeric_limits<double>::infinity());
  }
};

// An agent's state box at the interior points of a period (the knots keep theirs in
// PlanningProblem::state_bounds): one row per finite bound, lo - x <= 0 or x - hi <= 0.
class StateBoxConstraint final : public Constraint {
 public:
  StateBoxConstraint(std::string name, int offset, const Box& box);
  std::string name() const override { return name_; }
  int size() const override { return static_cast<int>(rows_.size()); }
  ConstraintStage stage() const override { return ConstraintStage::AllSteps; }
  const std::vector<int>& support() const override { return support_; }
  void evaluate(const double* x, double* g, double* jac) const override;
  bool hessian(const double*, const double*, double*) const override { return true; }  // linear

 private:
  struct Row {
    int coord;  // index into support_
    double sign, bound;
  };
  std::string name_;
  std::vector<int> support_;
  std::vector<Row> rows_;
};

class PairConstraint final : public Constraint {
 public:
  // With r = delta + both agents' margins: Inf: max(|dx|/rx, |dy|/ry) >= 1, enforced through a
  // smooth lower bound of the max whose corner has width `corner`; Two: ||d||_2 >= r.
  PairConstraint(std::string name, const AgentSpec& a, int offset_a, const AgentSpec& b, int offset_b,
                 Norm norm, double delta, std::shared_ptr<const MarginTable> ma,
                 std::shared_ptr<const MarginTable> mb, double corner, double buffer);
  std::string name() const override { return name_; }
  int size() const override { return 1; }
  ConstraintStage stage() const override { return ConstraintStage::AllSteps; }
  const std::vector<int>& support() const override { return support_; }
  void evaluate(const double* x, double* g, double* jac) const override;
  bool hessian(const double* x, const double* w, double* H) const override;
  double pair_reach() const override { return reach_; }
  double reach_decay() const override { return decay_; }

 private:
  std::string name_;
  const AgentSpec *a_, *b_;
  std::vector<int> support_;
  Norm norm_;
  double delta_;
  std::shared_ptr<const MarginTable> ma_, mb_;
  double corner_, buffer_;
  double reach_;
  double decay_ = 0.0;  // reach_decay(): 1 in the 2-norm, min r / max r in the max norm
  // g at d = p_a - p_b, and dg/dd in gd[D].
  double value(const double* d, const double* xa, const double* xb, double* gd) const;
  double value_inf3(const double* d, const WorkspaceMargin& m1, const WorkspaceMargin& m2, double* gd) const;
};

class FormationConstraint final : public Constraint {
 public:
  // lambda - mu + s <= ||p_a - p_b||_2 <= lambda + mu - s, s = both Euclidean margins + buffer.
  FormationConstraint(std::string name, const AgentSpec& a, int offset_a, const AgentSpec& b, int offset_b,
                      double lambda, double mu, std::shared_ptr<const MarginTable> ma,
                      std::shared_ptr<const MarginTable> mb, double buffer);
  std::string name() const override { return name_; }
  int size() const override { return 2; }
  ConstraintStage stage() const override { return ConstraintStage::AllSteps; }
  const std::vector<int>& support() const override { return support_; }
  void evaluate(const double* x, double* g, double* jac) const override;
  bool hessian(const double* x, const double* w, double* H) const override;

 private:
  std::string name_;
  const AgentSpec *a_, *b_;
  std::vector<int> support_;
  double lambda_, mu_;
  std::shared_ptr<const MarginTable> ma_, mb_;
  double buffer_;
};

// The eps-robust planning problem at horizon T (state bounds and goal shrunk by eps + buffer,
// workspace constraints grown by delta + margins + buffer). `problem` must outlive the result.
PlanningProblem assemble(const Problem& problem, int horizon, const AssemblyOptions& options = {});

}  // namespace marsyn::planning
