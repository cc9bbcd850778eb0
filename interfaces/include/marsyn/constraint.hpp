#pragma once
// Stage constraints g(x_k) <= 0 on the product state (obstacles, collisions, formation, bounds,
// goal), each reading only a few product coordinates so that planners can exploit sparsity.
#include <algorithm>
#include <limits>
#include <string>
#include <vector>

namespace marsyn {

// AllSteps: at every knot k = 1..T; Terminal: at k = T; AtSteps: only at the knots steps() lists
// (a mission stage's visit; PlanningProblem::constraints only, never `between`).
enum class ConstraintStage { AllSteps, Terminal, AtSteps };

class Constraint {
 public:
  virtual ~Constraint() = default;
  virtual std::string name() const = 0;       // e.g. "obstacle[0] vs drone3"
  virtual int size() const = 0;               // number of scalar inequalities
  virtual ConstraintStage stage() const = 0;
  // Product-state coordinates read by evaluate(), in the order of the Jacobian's columns.
  virtual const std::vector<int>& support() const = 0;
  // ConstraintStage::AtSteps: the knots where it applies, ascending. Empty for the other stages.
  virtual const std::vector<int>& steps() const {
    static const std::vector<int> none;
    return none;
  }
  // g (size()) at the product state x; jac (size() x support().size(), row-major) when non-null.
  virtual void evaluate(const double* x, double* g, double* jac) const = 0;
  // Adds sum_r w[r] d^2 g_r / dx^2 (support x support, row-major) to H, for second-order
  // planners. At the kinks of a piecewise-smooth g, the active piece's second derivative.
  // Returns false, leaving H alone, when this constraint does not provide it (the planner then
  // differences the Jacobian).
  virtual bool hessian(const double* x, const double* w, double* H) const {
    (void)x, (void)w, (void)H;
    return false;
  }
  // A broad-phase hint for planners that skip far-apart pairs (planner_support's
  // ProximityScreen): every row is satisfied (g <= 0) whenever the workspace points of the two
  // agents owning the first and the last support coordinate are farther apart than this, in the
  // max norm, whatever the rest of their states. Infinity (the default): no such bound.
  virtual double pair_reach() const { return std::numeric_limits<double>::infinity(); }
  // The same for a requirement on one agent (an obstacle): true, with a workspace box [lo, hi]
  // in x and y, when every row is satisfied (g <= 0) whenever the workspace point of the agent
  // owning the support lies outside the box in x or in y, whatever the rest of its state.
  // False (the default): no such box.
  virtual bool clear_outside(double lo[2], double hi[2]) const {
    (void)lo, (void)hi;
    return false;
  }
  // How fast the rows fall beyond that reach (or box): every row is at most -reach_decay() x s
  // once the points are s further apart than pair_reach() (or the point is s beyond the box in
  // x or y), so a screen for rows above -level widens by level / reach_decay(). 0 (the default):
  // no such rate; a screen then keeps the constraint for any level above 0.
  virtual double reach_decay() const { return 0.0; }
};

// Whether c applies at knot k of a horizon T.
inline bool applies_at(const Constraint& c, int k, int T) {
  switch (c.stage()) {
    case ConstraintStage::AllSteps: return true;
    case ConstraintStage::Terminal: return k == T;
    case ConstraintStage::AtSteps: {
      const auto& s = c.steps();
      return std::binary_search(s.begin(), s.end(), k);
    }
  }
  return true;
}

// A collision-geometry provider (the FCL plugin, or core's exact primitives): signed distance
// between a workspace point and an obstacle, with its gradient in the point.
class DistanceModel {
 public:
  virtual ~DistanceModel() = default;
  // Signed distance (negative inside) in the given norm, and d/dp in grad[2].
  virtual double distance(int obstacle, const double* p, double* grad) const = 0;
};

}  // namespace marsyn
